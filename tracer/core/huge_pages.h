// Transparent huge pages for the large arrays of heightfield/large_buffer.h.
#pragma once

namespace terracast {

// Installs the large-buffer advisor that marks each large array MADV_HUGEPAGE (Linux; elsewhere it installs
// nothing). Where the kernel's transparent huge pages are set to "madvise" (Debian's default) this is what
// enables them; with "always" it changes nothing, with "never" the advice is ignored. The memory used is the
// same: an array is touched whole once it is filled. The advisor then faults the array's pages in on the
// array-pass threads (MADV_POPULATE_WRITE, Linux 5.14 and later; heightfield/large_buffer.h), so that the thread
// that fills it does not take every fault alone. Call once at start-up.
void useHugePagesForLargeBuffers();

}  // namespace terracast
