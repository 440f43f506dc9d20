// Internal helpers shared by the model sources (not installed API).
#pragma once

#include "ggins/gravity/field.hpp"

namespace ggins::gravity {

// Adds the third derivatives of gm/|d| (d = r - r_mass) to t.
void add_point_mass_third(Real gm, const Vec3& d, Tensor3& t);

}  // namespace ggins::gravity
