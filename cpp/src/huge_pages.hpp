// Internal: asking the kernel for transparent huge pages on a large buffer.
#pragma once

#include <cstddef>

namespace animanifold {

// Inputs:
//   data, bytes  a buffer not yet written (its pages not yet faulted in)
// Outputs: none. Asks the kernel (madvise MADV_HUGEPAGE) to back the 2 MiB
//   aligned pages inside the buffer with transparent huge pages: writing it
//   then faults once per 2 MiB instead of once per 4 KiB, and reading it at
//   random (a slice's tets) misses the TLB far less. Linux's default THP mode,
//   "madvise", grants them only to buffers that ask. Buffers under 4 MiB and
//   systems without THP are left alone.
// Throws: nothing
void advise_huge_pages(void* data, std::size_t bytes) noexcept;

}  // namespace animanifold
