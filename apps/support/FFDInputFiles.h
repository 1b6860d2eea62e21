/*=========================================================================
 *
 *  Copyright NumFOCUS
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef FFDInputFiles_h
#define FFDInputFiles_h

// The one check every input file of the module's command-line programs passes before a library reader sees it:
// a regular file (symbolic links followed), not empty, not larger than a bound. A FIFO, a device or a directory
// would make ITK's and VTK's readers block forever or read until memory runs out; they are refused instead.

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <string>
#include <sys/stat.h>
#include <sys/types.h>
#include <system_error>
#include <unistd.h>

namespace ffd
{
/** Size bounds of the inputs (bytes): larger files are refused before parsing. */
constexpr std::uintmax_t MaximumMeshFileSize = std::uintmax_t{ 4 } << 30;      // 4 GiB
constexpr std::uintmax_t MaximumTransformFileSize = std::uintmax_t{ 1 } << 30; // 1 GiB
constexpr std::uintmax_t MaximumImageFileSize = std::uintmax_t{ 16 } << 30;    // 16 GiB

/** What CheckInputFile found: the file as the path resolves (symbolic links followed), its size and identity
 * (device and inode, to tell whether two names are the same file). */
struct InputFileInfo
{
  std::string    resolvedPath;
  std::uintmax_t size{ 0 };
  dev_t          device{ 0 };
  ino_t          inode{ 0 };
};

/** The kind of a non-regular file, for messages: "a FIFO", "a character device", ... */
inline std::string
FileKindOf(mode_t mode)
{
  if (S_ISDIR(mode))
  {
    return "a directory";
  }
  if (S_ISFIFO(mode))
  {
    return "a FIFO";
  }
  if (S_ISCHR(mode))
  {
    return "a character device";
  }
  if (S_ISBLK(mode))
  {
    return "a block device";
  }
  if (S_ISSOCK(mode))
  {
    return "a socket";
  }
  return "not a file";
}

/** Describes a byte count for messages: "5368709120 bytes (5.0 GiB)". */
inline std::string
ByteCountText(std::uintmax_t bytes)
{
  const double gib = static_cast<double>(bytes) / static_cast<double>(std::uintmax_t{ 1 } << 30);
  char         buffer[64];
  std::snprintf(buffer, sizeof(buffer), " bytes (%.1f GiB)", gib);
  return std::to_string(bytes) + buffer;
}

/** Checks the input file \c fileName before any library reads it; \c what names it in messages ("source mesh",
 * "the templates", "reference image"). The path is resolved (symbolic links followed) and the file opened once
 * with O_RDONLY | O_NONBLOCK | O_CLOEXEC (a FIFO without a writer does not block the open), and the open
 * descriptor is checked with fstat: anything but a regular file, an empty file and a file larger than
 * \c maximumSize bytes are refused with <tt>cannot read WHAT 'NAME': PROBLEM</tt>, thrown as \c TError.
 *
 * ITK's and VTK's readers take a file name, not a descriptor, and choose their format by its extension: the
 * caller reads \c fileName again by name after this check. A file replaced between the check and the read
 * (a race only the user's own processes can run) is accepted as a risk. */
template <typename TError>
InputFileInfo
CheckInputFile(const std::string & fileName, const std::string & what, std::uintmax_t maximumSize)
{
  const auto refuse = [&](const std::string & problem) {
    return TError("cannot read " + what + " '" + fileName + "': " + problem);
  };
  if (fileName.empty())
  {
    throw TError("cannot read " + what + ": the file name is empty");
  }
  // stat() first, so that a device is refused without being opened (opening some devices has effects).
  struct stat status
  {};
  if (::stat(fileName.c_str(), &status) != 0)
  {
    const int error = errno;
    throw refuse(error == ENOENT || error == ENOTDIR
                   ? std::string("no such readable file")
                   : "no such readable file (" + std::string(std::strerror(error)) + ")");
  }
  if (!S_ISREG(status.st_mode))
  {
    throw refuse("not a regular file (" + FileKindOf(status.st_mode) + ")");
  }
  const int descriptor = ::open(fileName.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0)
  {
    throw refuse("no such readable file (" + std::string(std::strerror(errno)) + ")");
  }
  const int checked = ::fstat(descriptor, &status);
  ::close(descriptor);
  if (checked != 0)
  {
    throw refuse("cannot inspect the file (" + std::string(std::strerror(errno)) + ")");
  }
  if (!S_ISREG(status.st_mode)) // replaced between stat() and open()
  {
    throw refuse("not a regular file (" + FileKindOf(status.st_mode) + ")");
  }
  const auto size = static_cast<std::uintmax_t>(status.st_size);
  if (size == 0)
  {
    throw refuse("the file is empty");
  }
  if (size > maximumSize)
  {
    throw refuse("the file has " + ByteCountText(size) + ", more than the " + ByteCountText(maximumSize) +
                 " an input of this kind may have");
  }
  InputFileInfo   info;
  std::error_code resolveError;
  info.resolvedPath = std::filesystem::canonical(fileName, resolveError).string();
  if (resolveError)
  {
    info.resolvedPath = fileName;
  }
  info.size = size;
  info.device = status.st_dev;
  info.inode = status.st_ino;
  return info;
}

/** CheckInputFile for the --templates file of ffd-match (an ITK transform file, at most 1 GiB). */
template <typename TError>
InputFileInfo
CheckTemplatesFile(const std::string & fileName)
{
  return CheckInputFile<TError>(fileName, "the templates", MaximumTransformFileSize);
}
} // namespace ffd

#endif // FFDInputFiles_h
