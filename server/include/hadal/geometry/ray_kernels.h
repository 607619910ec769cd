// Which of Embree's kernels trace a world's rays (YAML world.ray_kernels; docs/ARCHITECTURE.md, "One ray-cast world").
#pragma once

namespace hadal::geometry {

enum class RayKernels {
  // Embree's fastest kernels for this CPU (AVX-512, AVX2, ...), hits as Embree computes them: the same
  // bits run after run on one machine, but the last bits of distances and normals (and, at a triangle
  // edge, which triangle) can differ between CPUs.
  kNative,
  // Embree's SSE4.2 kernels on every x86-64 CPU, and every hit recomputed in double precision from the
  // triangle it found, with edge, vertex and grazing hits decided by Hadal's own rule
  // (geometry/hit_refinement.h): the same bits on every x86-64 CPU of one libm kind (glibc's FMA kernels
  // or not; tests/regression/README.md, "Machines"), at a cost in speed (docs/benchmarks.md, "Portable
  // ray kernels").
  kPortable,
};

}  // namespace hadal::geometry
