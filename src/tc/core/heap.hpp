#pragma once
// The C library's heap between the phases of a run. Memory a phase frees stays in the process
// while any later allocation sits above it in the heap (glibc returns only the heap's free top
// by itself): the 10⁶-dof case kept 0.6 GiB of its pattern analysis resident through every
// factorisation after it (issue 39).

namespace tc::core {

/// Returns the free pages inside the heap to the system (glibc's malloc_trim) when its free
/// chunks below the top hold at least `at_least` bytes, so that a small run keeps its pages
/// for reuse without faulting them in again; nothing on other C libraries. A walk over the
/// heap's free chunks: milliseconds.
void release_free_heap(double at_least = 64.0 * 1024.0 * 1024.0);

}  // namespace tc::core
