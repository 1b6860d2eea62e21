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
#include "FFDOutputFiles.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace ffd
{
namespace
{
// Temporary files to remove when a signal ends the run. The handler may only use async-signal-safe calls, so the
// names live in fixed buffers, and an entry counts only once it is complete.
constexpr std::size_t    MaximumTemporaries = 64;
char                     g_Temporaries[MaximumTemporaries][4096];
std::atomic<bool>        g_TemporaryUsed[MaximumTemporaries];
std::atomic<std::size_t> g_NumberOfTemporaries{ 0 };

extern "C" void
RemoveTemporariesAndReraise(int signalNumber)
{
  const std::size_t n = g_NumberOfTemporaries.load();
  for (std::size_t i = 0; i < n && i < MaximumTemporaries; ++i)
  {
    if (g_TemporaryUsed[i].load())
    {
      unlink(g_Temporaries[i]);
    }
  }
  std::signal(signalNumber, SIG_DFL);
  raise(signalNumber);
}

void
InstallSignalCleanup()
{
  static bool installed = false;
  if (installed)
  {
    return;
  }
  installed = true;
  // A FIFO whose reader went away makes write() fail with EPIPE, which the checks report, instead of ending the run.
  std::signal(SIGPIPE, SIG_IGN);
  for (const int signalNumber : { SIGINT, SIGTERM, SIGHUP, SIGXFSZ })
  {
    struct sigaction previous;
    sigaction(signalNumber, nullptr, &previous);
    if (previous.sa_handler == SIG_IGN)
    {
      // Kept ignored (e.g. under nohup); an ignored SIGXFSZ makes writes past the limit fail with EFBIG instead,
      // which the checks of every write catch.
      continue;
    }
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = RemoveTemporariesAndReraise;
    sigemptyset(&action.sa_mask);
    sigaction(signalNumber, &action, nullptr);
  }
}

std::size_t
RegisterTemporary(const std::string & name)
{
  const std::size_t slot = g_NumberOfTemporaries.load();
  if (slot >= MaximumTemporaries || name.size() >= sizeof(g_Temporaries[0]))
  {
    return MaximumTemporaries;
  }
  std::memcpy(g_Temporaries[slot], name.c_str(), name.size() + 1);
  g_TemporaryUsed[slot].store(true);
  g_NumberOfTemporaries.store(slot + 1);
  return slot;
}

void
UnregisterTemporary(std::size_t slot)
{
  if (slot < MaximumTemporaries)
  {
    g_TemporaryUsed[slot].store(false);
  }
}

std::string
Lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string
Reason(int error)
{
  return std::strerror(error);
}

// Whether two existing paths are the same file (after following symbolic links).
bool
SameFile(const struct stat & a, const struct stat & b)
{
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// Writes all of \c text to \c descriptor; false with errno set on failure.
bool
WriteAll(int descriptor, const std::string & text)
{
  const char * data = text.data();
  std::size_t  left = text.size();
  while (left > 0)
  {
    const ssize_t written = write(descriptor, data, left);
    if (written < 0)
    {
      if (errno == EINTR)
      {
        continue;
      }
      return false;
    }
    if (written == 0)
    {
      errno = EIO;
      return false;
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  return true;
}

// Flushes the folder of \c path to disk (so that a rename is durable); errors are not fatal.
void
SyncFolder(const std::string & path)
{
  const std::string folder = std::filesystem::path(path).parent_path().string();
  const int         descriptor = open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (descriptor >= 0)
  {
    fsync(descriptor);
    close(descriptor);
  }
}
} // namespace

struct OutputFiles::Entry
{
  std::string path;        // as the user gave it
  std::string destination; // where the file is renamed to: the path, or the file a symbolic link names
  std::string what;        // the option, for messages
  std::string temporary;   // where the content is written (empty for a device)
  std::string backup;      // the previous file during Commit(), to restore on failure
  std::size_t slot{ MaximumTemporaries };
  bool        device{ false }; // a character device or FIFO, written in place
  bool        text{ false };
  bool        textWritten{ false };
  std::string deviceText;
  int         descriptor{ -1 }; // a device or FIFO, open from Add() on (closing a FIFO would end its reader's input)
  bool        committed{ false };
};

OutputFiles::OutputFiles(std::string program)
  : m_Program(std::move(program))
{
  InstallSignalCleanup();
}

OutputFiles::~OutputFiles()
{
  for (const auto & entry : m_Entries)
  {
    if (!entry->committed && !entry->temporary.empty())
    {
      unlink(entry->temporary.c_str());
    }
    if (entry->descriptor >= 0)
    {
      close(entry->descriptor);
    }
    UnregisterTemporary(entry->slot);
  }
}

void
OutputFiles::AddInput(const std::string & path)
{
  m_Inputs.push_back(path);
}

std::string
OutputFiles::Add(const std::string &              path,
                 const std::string &              what,
                 const std::vector<std::string> & extensions,
                 bool                             text)
{
  const std::filesystem::path given(path);
  const std::string           name = given.filename().string();
  if (path.empty() || name.empty() || name == "." || name == "..")
  {
    throw std::runtime_error(what + " '" + path + "' is not a file name");
  }
  const std::size_t dot = name.find('.');
  const std::string ending = dot == std::string::npos ? std::string() : Lower(name.substr(dot));
  if (!extensions.empty() && std::none_of(extensions.begin(), extensions.end(), [&](const std::string & e) {
        return ending.size() >= e.size() && ending.compare(ending.size() - e.size(), e.size(), e) == 0;
      }))
  {
    std::string list;
    for (std::size_t i = 0; i < extensions.size(); ++i)
    {
      list += (i == 0 ? "" : (i + 1 == extensions.size() ? " or " : ", ")) + extensions[i];
    }
    throw std::runtime_error(what + " must name a file ending in " + list + ", not '" + path + "'");
  }

  auto        entry = std::make_unique<Entry>();
  struct stat existing;
  const bool  exists = stat(path.c_str(), &existing) == 0;
  struct stat linkStat;
  const bool  isLink = lstat(path.c_str(), &linkStat) == 0 && S_ISLNK(linkStat.st_mode);
  if (isLink && !exists)
  {
    throw std::runtime_error("cannot write " + what + " '" + path + "': a symbolic link to nothing");
  }
  if (exists)
  {
    if (S_ISDIR(existing.st_mode))
    {
      throw std::runtime_error("cannot write " + what + " '" + path + "': it is a folder");
    }
    if (S_ISCHR(existing.st_mode) || S_ISFIFO(existing.st_mode))
    {
      if (!text)
      {
        throw std::runtime_error("cannot write " + what + " '" + path +
                                 "': it is a device or FIFO, and this output must be a regular file");
      }
      entry->device = true;
    }
    else if (!S_ISREG(existing.st_mode))
    {
      throw std::runtime_error("cannot write " + what + " '" + path + "': not a regular file");
    }
    for (const std::string & input : m_Inputs)
    {
      struct stat inputStat;
      if (stat(input.c_str(), &inputStat) == 0 && SameFile(existing, inputStat) && !entry->device)
      {
        throw std::runtime_error(what + " '" + path + "' is the input '" + input +
                                 "' (the same file): an output never replaces an input");
      }
    }
  }
  std::error_code   ignored;
  const std::string canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(given), ignored).string();
  for (const auto & other : m_Entries)
  {
    struct stat       otherStat;
    const bool        sameFile = exists && stat(other->path.c_str(), &otherStat) == 0 && SameFile(existing, otherStat);
    const std::string otherCanonical =
      std::filesystem::weakly_canonical(std::filesystem::absolute(other->path), ignored).string();
    if (sameFile || canonical == otherCanonical)
    {
      throw std::runtime_error(what + " and " + other->what + " name the same file '" + path + "'");
    }
  }

  entry->path = path;
  entry->what = what;
  entry->text = text;
  if (entry->device)
  {
    // Opened now, without blocking: a FIFO without a reader is refused at once.
    entry->descriptor = open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (entry->descriptor < 0)
    {
      const int error = errno;
      throw std::runtime_error(
        "cannot write " + what + " '" + path +
        "': " + (error == ENXIO && S_ISFIFO(existing.st_mode) ? std::string("the FIFO has no reader") : Reason(error)));
    }
    m_Entries.push_back(std::move(entry));
    return path;
  }

  // A symbolic link is written through: the file it names is replaced, the link stays.
  std::error_code linkError;
  entry->destination = isLink ? std::filesystem::canonical(given, linkError).string() : path;
  if (linkError)
  {
    throw std::runtime_error("cannot write " + what + " '" + path + "': " + linkError.message());
  }
  const std::string folder = std::filesystem::path(entry->destination).parent_path().string();
  const std::string stem = dot == std::string::npos ? name : name.substr(0, dot);
  entry->temporary = (folder.empty() ? std::string() : folder + "/") + "." + m_Program + "-" +
                     std::to_string(getpid()) + "-" + std::to_string(m_Entries.size()) + "-" + stem + ending;
  // Created now (exclusively): the folder is writable and the name is ours.
  const int descriptor = open(entry->temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (descriptor < 0)
  {
    const int error = errno;
    throw std::runtime_error("cannot write " + what + " '" + path + "': " +
                             (error == ENOENT || error == ENOTDIR
                                ? std::string("the folder does not exist")
                                : "the folder is not writable (" + Reason(error) + ")"));
  }
  close(descriptor);
  entry->slot = RegisterTemporary(entry->temporary);
  const std::string temporary = entry->temporary;
  m_Entries.push_back(std::move(entry));
  return temporary;
}

OutputFiles::Entry &
OutputFiles::Find(const std::string & path)
{
  for (const auto & entry : m_Entries)
  {
    if (entry->path == path)
    {
      return *entry;
    }
  }
  throw std::logic_error("output '" + path + "' was not declared");
}

void
OutputFiles::WriteText(const std::string & path, const std::string & text)
{
  Entry & entry = this->Find(path);
  entry.textWritten = true;
  if (entry.device)
  {
    entry.deviceText = text; // written at Commit(), after every other output succeeded
    return;
  }
  const int descriptor = open(entry.temporary.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (descriptor < 0)
  {
    throw std::runtime_error("cannot write " + entry.what + " '" + path + "': " + Reason(errno));
  }
  const bool written = WriteAll(descriptor, text);
  const int  writeError = errno;
  const bool synced = written && fsync(descriptor) == 0;
  const int  syncError = errno;
  const bool closed = close(descriptor) == 0;
  if (!written || !synced || !closed)
  {
    throw std::runtime_error("cannot write " + entry.what + " '" + path +
                             "': " + Reason(!written ? writeError : (!synced ? syncError : errno)));
  }
}

void
OutputFiles::Commit()
{
  // 1. Every temporary file is on disk and not empty.
  for (const auto & entry : m_Entries)
  {
    if (entry->device)
    {
      continue;
    }
    const int   descriptor = open(entry->temporary.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat written;
    if (descriptor < 0 || fsync(descriptor) != 0 || fstat(descriptor, &written) != 0)
    {
      const int error = errno;
      if (descriptor >= 0)
      {
        close(descriptor);
      }
      throw std::runtime_error("cannot write " + entry->what + " '" + entry->path + "': " + Reason(error));
    }
    close(descriptor);
    if (written.st_size == 0)
    {
      throw std::runtime_error("cannot write " + entry->what + " '" + entry->path +
                               "': nothing was written (the disk is full or a file size limit was reached)");
    }
  }
  // 2. Devices and FIFOs get their text (nothing is renamed yet, so a failure here changes no file).
  for (const auto & entry : m_Entries)
  {
    if (!entry->device)
    {
      continue;
    }
    const int descriptor = entry->descriptor;
    fcntl(descriptor, F_SETFL, fcntl(descriptor, F_GETFL) & ~O_NONBLOCK); // the reader is there: block as usual
    const bool written = WriteAll(descriptor, entry->deviceText);
    const int  error = errno;
    close(descriptor);
    entry->descriptor = -1;
    if (!written)
    {
      throw std::runtime_error("cannot write " + entry->what + " '" + entry->path + "': " + Reason(error));
    }
  }
  // 3. All renamed together: an existing file is kept under a backup name until every rename succeeded.
  std::size_t done = 0;
  try
  {
    for (const auto & entry : m_Entries)
    {
      if (entry->device)
      {
        ++done;
        continue;
      }
      struct stat existing;
      if (lstat(entry->destination.c_str(), &existing) == 0 && S_ISREG(existing.st_mode))
      {
        entry->backup = entry->temporary + ".previous";
        if (link(entry->destination.c_str(), entry->backup.c_str()) != 0)
        {
          entry->backup.clear(); // no hard links here: the rename still replaces the file atomically
        }
      }
      if (std::rename(entry->temporary.c_str(), entry->destination.c_str()) != 0)
      {
        const int error = errno;
        if (!entry->backup.empty())
        {
          unlink(entry->backup.c_str());
          entry->backup.clear();
        }
        throw std::runtime_error("cannot move the result into " + entry->what + " '" + entry->path +
                                 "': " + Reason(error));
      }
      entry->committed = true;
      ++done;
    }
  }
  catch (...)
  {
    for (std::size_t i = 0; i < done; ++i)
    {
      Entry & entry = *m_Entries[i];
      if (entry.device || !entry.committed)
      {
        continue;
      }
      if (!entry.backup.empty())
      {
        std::rename(entry.backup.c_str(), entry.destination.c_str());
      }
      else
      {
        unlink(entry.destination.c_str());
      }
      entry.committed = false;
    }
    throw;
  }
  for (const auto & entry : m_Entries)
  {
    if (!entry->backup.empty())
    {
      unlink(entry->backup.c_str());
    }
    if (!entry->device)
    {
      SyncFolder(entry->destination);
    }
  }
}
} // namespace ffd
