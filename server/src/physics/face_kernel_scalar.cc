// The face loops compiled without vectorisation (server/CMakeLists.txt: -fno-tree-vectorize
// -fno-tree-slp-vectorize), one face at a time: the reference the vector clones are tested against (face_kernel.h).
#include <algorithm>
#include <cmath>

#include "face_kernel.h"

#define HADAL_FACE_KERNEL

namespace hadal::physics::face_kernel {
namespace scalar {
#include "face_kernel.inc"
}  // namespace scalar

const Kernel& scalar_kernel() { return scalar::kernel_table(); }

}  // namespace hadal::physics::face_kernel
