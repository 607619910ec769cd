// HADAL_VECTOR_KERNEL: a function whose loops the compiler vectorizes is compiled three times, for
// AVX-512 (16 floats a vector), AVX2 (8) and the x86-64 baseline (SSE2, 4), and the CPU picks at load
// time (GCC function multiversioning). The files that use it are compiled with server/CMakeLists.txt's
// HADAL_VECTOR_LOOP_FLAGS: no FMA contraction (GCC contracts a * b + c by default in C++, and AVX-512
// implies FMA), so every version does the same IEEE operations per element and gives the same bits
// (render/fast_math_test.cc; whole frames compared across builds).
// Such a function must not let an exception out: GCC 12 takes a target_clones function for nothrow, so
// an exception leaving one (thrown in it or in anything it calls) ends in std::terminate, and handlers
// in its callers are dropped as dead code. Validate before calling one, or have it return a verdict
// and throw from the caller (the ray caster's rays_valid and validate_rays).
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define HADAL_VECTOR_KERNEL __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define HADAL_VECTOR_KERNEL
#endif
