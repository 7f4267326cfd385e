#include "pnc/damage/reference.hpp"

#include "pnc/core/error.hpp"

namespace pnc::damage {

NdmParameters dissertation_parameters(Model m) {
  constexpr double GPa = 1e9;
  NdmParameters p;
  p.model = m;
  if (m == Model::pnc) {
    p["C11"] = 1.155 * GPa;
    p["C22"] = 1.153 * GPa;
    p["C33"] = 0.648 * GPa;
    p["C12"] = 0.708 * GPa;
    p["C13"] = 0.585 * GPa;
    p["C23"] = 0.563 * GPa;
    p["C44"] = 0.189 * GPa;
    p["C55"] = 0.038851 * GPa;
    p["C66"] = 0.189 * GPa; // not printed (case 6 not fitted): decision D9
    p["A1"] = -0.99 / 2 * GPa;
    p["A5"] = -0.979 / 2 * GPa;
    p["A9"] = -0.528 / 2 * GPa;
    p["A10"] = -0.60 * GPa;
    p["A11"] = -0.548 * GPa;
    p["A13"] = -0.47 * GPa;
    p["A15"] = -0.588 * GPa;
    p["A17"] = -0.435 * GPa;
    p["A18"] = -0.504 * GPa;
    p["A22"] = -0.337 * GPa;
    p["A24"] = -0.337 * GPa; // not printed: decision D9
    p["A26"] = 0.0;
    p["alpha"] = 0.861;
  } else {
    p["C11"] = 0.559 * GPa;
    p["C12"] = 0.447 * GPa;
    p["C44"] = 0.109 * GPa;
    // Table 6.10 pairs its rows in order (C12 with B1, C22 with 2B2, C23 with B3), and each
    // printed number is the damage slope of its row's stress (D2's rule): sigma22 (diagonal,
    // 2 B1 D in this code's naming) -0.405, sigma11 (off-diagonal, B2 D) -0.304 (D9).
    p["B1"] = -0.405 / 2 * GPa;
    p["B2"] = -0.304 * GPa;
    p["B4"] = -0.757 * GPa;
    p["alpha"] = 0.941;
  }
  return p;
}

} // namespace pnc::damage

#include <limits>

namespace pnc::damage {
const std::vector<PrintedRegression>& printed_regression(Model m) {
  constexpr double G = 1e9;
  const double na = std::numeric_limits<double>::quiet_NaN();
  static const std::vector<PrintedRegression> pnc = {
      {1, 0, "C11", 1.155 * G, 0.989, "2A1", -0.99 * G, 0.999},
      {1, 1, "C12", 0.763 * G, 0.993, "A10", -0.60 * G, 0.997},
      {1, 2, "C13", 0.585 * G, 0.976, "A13", -0.47 * G, 0.999},
      {2, 0, "C12", 0.708 * G, 0.979, "A11", -0.548 * G, 0.996},
      {2, 1, "C22", 1.153 * G, 0.994, "2A5", -0.979 * G, 0.998},
      {2, 2, "C23", 0.563 * G, 0.960, "A17", -0.435 * G, 0.998},
      {3, 0, "C13", 0.733 * G, 0.973, "A15", -0.588 * G, 0.997},
      {3, 1, "C23", 0.633 * G, 0.973, "A18", -0.504 * G, 0.995},
      {3, 2, "C33", 0.648 * G, 0.993, "2A9", -0.528 * G, 0.994},
      {4, 3, "C44", 0.189 * G, 0.941, "A22", -0.337 * G, 0.959},
      {5, 4, "C55", 0.038851 * G, na, "A26", 0.0, na}};
  // Tables 6.10-6.11 for the pure polymer, rows paired in the printed order as in Tables
  // 6.6-6.9 (sigma11 -> C12, B1; sigma22 -> C22, 2B2; sigma33 -> C23, B3); decision D9.
  static const std::vector<PrintedRegression> pp = {
      {2, 0, "C12", 0.447 * G, 0.981, "B1", -0.304 * G, 0.994},
      {2, 1, "C22", 0.559 * G, 0.962, "2B2", -0.405 * G, 0.994},
      {2, 2, "C23", 0.498 * G, 0.92, "B3", -0.355 * G, 0.997},
      {6, 5, "C66", 0.109 * G, 0.941, "B4", -0.757 * G, 0.96}};
  return m == Model::pnc ? pnc : pp;
}
} // namespace pnc::damage
