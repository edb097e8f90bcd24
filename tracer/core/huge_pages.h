// Transparent huge pages for the large arrays of heightfield/large_buffer.h.
#pragma once

namespace terracast {

// Installs the large-buffer advisor that marks each large array MADV_HUGEPAGE (Linux; elsewhere it installs
// nothing). Where the kernel's transparent huge pages are set to "madvise" (Debian's default) this is what
// enables them; with "always" it changes nothing, with "never" the advice is ignored. The memory used is the
// same: an array is touched whole once it is filled. Call once at start-up.
void useHugePagesForLargeBuffers();

}  // namespace terracast
