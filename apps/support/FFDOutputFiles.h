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
#ifndef FFDOutputFiles_h
#define FFDOutputFiles_h

// The output files of one run of a command-line program, checked before any work and committed together or not at
// all (ffd-match, ffd-voxelize):
//  - every output path is checked when it is declared: a file name, in a writable folder, with an extension the
//    caller accepts (case-insensitive), not a folder, not one of the run's inputs (same path, hard link or
//    symbolic link: the same file), not another output;
//  - regular files are written under a temporary name in the same folder (created at once, so the folder is known
//    to be writable), then flushed to disk, checked and renamed into place together, after every output was
//    written; if one rename fails, the files already moved are restored;
//  - a text output (a report) that names a character device or a FIFO is written into it, never replaced;
//  - temporary files are removed on every failure and on SIGINT, SIGTERM, SIGHUP and SIGXFSZ.

#include <memory>
#include <string>
#include <vector>

namespace ffd
{
class OutputFiles
{
public:
  /** \c program names the temporary files (".PROGRAM-PID-N-name") and the messages. */
  explicit OutputFiles(std::string program);
  ~OutputFiles();
  OutputFiles(const OutputFiles &) = delete;
  OutputFiles &
  operator=(const OutputFiles &) = delete;

  /** A file the run reads: no output may be it. Call before Add(). */
  void
  AddInput(const std::string & path);

  /** Declares the output \c path (\c what names it in messages, e.g. "--report"); \c extensions lists the accepted
   * endings in lower case (e.g. ".off"), none = any. A text output (written by WriteText()) may name a character
   * device or FIFO. Throws std::runtime_error with the reason when the output cannot be written. Returns the name to
   * write to: a temporary file in the same folder whose ending is the lower-case ending of \c path. */
  std::string
  Add(const std::string & path, const std::string & what, const std::vector<std::string> & extensions, bool text);

  /** Writes \c text as the content of the text output \c path (as given to Add()), checking every write. */
  void
  WriteText(const std::string & path, const std::string & text);

  /** Moves every output into place: each temporary file is flushed to disk and checked (not empty), device
   * outputs are written, then all are renamed; on any failure nothing is left changed. */
  void
  Commit();

private:
  struct Entry;
  Entry &
  Find(const std::string & path);

  std::string                         m_Program;
  std::vector<std::unique_ptr<Entry>> m_Entries;
  std::vector<std::string>            m_Inputs;
};
} // namespace ffd

#endif // FFDOutputFiles_h
