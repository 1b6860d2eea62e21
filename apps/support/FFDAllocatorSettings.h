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
#ifndef FFDAllocatorSettings_h
#define FFDAllocatorSettings_h

// How the module's command-line programs ask the C library's allocator to treat their memory.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#if defined(__GLIBC__)
#  include <malloc.h>
#  include <sys/mman.h>
#  include <unistd.h>
#endif

namespace ffd
{
/** Sets the allocator up for a program that allocates and frees buffers of the same sizes many times (images,
 * sample arrays, solver work space), as a match does. Call it first in main. Without it, glibc gives every block
 * of 128 KiB or more back to the system when it is freed and trims its heap whenever 128 KiB lie free at the top,
 * so the next buffer of that size is faulted in afresh, 4 KiB at a time, every page zeroed by the kernel. Here:
 * - freed blocks up to 256 MiB stay with the program and are handed out again (larger ones, a large image, still
 *   get their own mapping and go back at once); the heap is trimmed only when 1 GiB lies free at its top. The
 *   resident memory stays at the run's peak: freed memory is reused, not added to.
 * - the first 256 MiB of heap address space are reserved at once and marked for transparent huge pages
 *   (madvise MADV_HUGEPAGE), so the kernel backs the heap with 2 MiB pages where it can: a five-hundredth of the
 *   faults, and fewer TLB misses. Untouched address space costs no memory (whole huge pages round the peak up a
 *   little: 64 -> 70 MB on cheese); where the kernel has no free huge page or transparent huge pages are off, it
 *   uses 4 KiB pages as before.
 * On the benchmark's cases this removed 80-95 % of ffd-match's page faults (cheese 11 800 -> 2 300, bunny00 34 800 ->
 * 2 000) and 10-25 % of its CPU time, with bit-identical results (benchmark/PEERS_MESH.md, "The allocator and
 * start-up"). Nothing is done where the C library is not glibc. */
inline void
KeepFreedMemoryForReuse()
{
#if defined(__GLIBC__)
  constexpr std::size_t mebibyte = 1024u * 1024u;
  constexpr std::size_t topPad = 64u * mebibyte;
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(256u * mebibyte));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(1024u * mebibyte));
  mallopt(M_TOP_PAD, static_cast<int>(topPad));

  // One block just below the mapping threshold comes from the heap, which grows past it by the top pad; free, it
  // stays there (below the trim threshold) for the run's buffers. Advised only when the block is at the top of the
  // heap, i.e. the heap is the program break's (not with another allocator, e.g. a sanitizer's).
  constexpr std::size_t hugePage = 2u * mebibyte;
  constexpr std::size_t reserve = 254u * mebibyte;
  void *                block = std::malloc(reserve);
  if (block == nullptr)
  {
    return;
  }
  const auto begin = reinterpret_cast<std::uintptr_t>(block);
  const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
  if (end >= begin + reserve && end - (begin + reserve) <= topPad + hugePage)
  {
    const std::uintptr_t alignedBegin = (begin + hugePage - 1) & ~static_cast<std::uintptr_t>(hugePage - 1);
    // Advice only: a kernel without transparent huge pages refuses it, and nothing changes.
    madvise(reinterpret_cast<void *>(alignedBegin), end - alignedBegin, MADV_HUGEPAGE);
  }
  std::free(block);
#endif
}
} // namespace ffd

#endif // FFDAllocatorSettings_h
