// Process-wide allocator settings for programs that render camera frames (hadald, hadal-render, the
// benchmarks): a frame allocates and frees a few buffers of megabytes (radiance, depth, noise, the
// bands' hit arrays) on the ray-cast workers. With glibc's defaults the larger ones are mapped afresh
// and the freed heap tops are trimmed back to the kernel, so every frame pays page faults and the
// kernel's zeroing of each page again (measured on the default scenario's frame: 107 000 page faults
// in 30 frames, 8 % of the CPU time; 23 000 with these settings, bench/camera_frame.cc). Keeping
// buffers up to 32 MiB in the heap and not trimming below 512 MiB of free top lets frames reuse the
// same pages; the process's resident size stays at its peak instead of falling between frames.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace hadal {

// Call once at the start of main(), before any thread starts. No-op without glibc.
inline void keep_frame_buffers_mapped() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
#endif
}

}  // namespace hadal
