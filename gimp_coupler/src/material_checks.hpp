#pragma once
// Checks shared by the GIMP laws' sources (materials.cpp, hyperelastic.cpp). No units beyond
// those named.

namespace pnc::gimp::detail {

/// Throws std::runtime_error naming `law` and J unless J = det F is finite and > 0.
void check_jacobian(double J, const char* law);

} // namespace pnc::gimp::detail
