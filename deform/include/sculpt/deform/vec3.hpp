#pragma once
// deform's 3-vector is the project's one (sculpt/base/vec3.hpp), named here so deform's code
// and its users keep writing deform::Vec3, deform::dot, ...

#include "sculpt/base/vec3.hpp"

namespace sculpt::deform {

using base::cross;
using base::dot;
using base::is_finite;
using base::norm;
using base::normalized;
using base::squared_norm;
using base::Vec3;

}  // namespace sculpt::deform
