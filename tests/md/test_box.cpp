// pnc/md/box.hpp: the box after box_change checked against the edge vectors F a, F b, F c
// (or, for a rotating F, against the metric of F H), and the six deformation cases (D316).
#include "pnc/core/error.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/md/box.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <sstream>
#include <string>
#include <vector>

// box_change (D316) against the edge vectors of the box: the LAMMPS box has edges
// a = (Lx,0,0), b = (xy,Ly,0), c = (xz,yz,Lz); after F they must be F a, F b, F c, computed here
// as one matrix product, with the centre of every length kept.
namespace {
struct Box {
  double lo[3], hi[3], xy = 0, xz = 0, yz = 0;
};
Box parse_change(const std::vector<double>& ref, const std::string& cmd) {
  Box b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = ref[a];
    b.hi[a] = ref[a + 3];
  }
  b.xy = ref[6], b.xz = ref[7], b.yz = ref[8];
  std::istringstream in(cmd);
  std::string w;
  in >> w >> w; // change_box all
  while (in >> w && w != "remap") {
    std::string fin;
    in >> fin;
    EXPECT_EQ(fin, "final") << cmd;
    if (w == "x" || w == "y" || w == "z") {
      const int a = w[0] - 'x';
      in >> b.lo[a] >> b.hi[a];
    } else if (w == "xy") {
      in >> b.xy;
    } else if (w == "xz") {
      in >> b.xz;
    } else if (w == "yz") {
      in >> b.yz;
    } else {
      ADD_FAILURE() << "unexpected keyword " << w << " in " << cmd;
    }
  }
  return b;
}
Eigen::Matrix3d edges(const Box& b) { // columns a, b, c
  Eigen::Matrix3d e;
  e << b.hi[0] - b.lo[0], b.xy, b.xz, 0, b.hi[1] - b.lo[1], b.yz, 0, 0, b.hi[2] - b.lo[2];
  return e;
}
} // namespace

TEST(MdBox, BoxChangeTakesTheEdgesToFTimesThemAboutTheCentre) {
  const std::vector<double> ref = {-3.0, 1.0, 2.0, 17.0, 26.0, 32.0, 1.5, -0.5, 2.5};
  Box r;
  r = parse_change(ref, "change_box all remap units box");
  const Eigen::Matrix3d E0 = edges(r);
  Eigen::Matrix3d F;
  F << 1.03, 0.02, -0.04, 0.0, 0.97, 0.05, 0.0, 0.0, 1.1; // every upper entry, all lengths
  const std::string cmd = pnc::md::box_change(pnc::md::LmpBox::from_vector(ref, "test"), F);
  const Box b = parse_change(ref, cmd);
  // %.15g keeps 15 significant digits: relative round-off 5e-15 of the largest length 30 A
  const double tol = 1e-12;
  EXPECT_TRUE(((edges(b) - F * E0).array().abs() < tol).all()) << cmd << "\n" << edges(b);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(b.lo[a] + b.hi[a], ref[a] + ref[a + 3], tol) << "centre of axis " << a;
  const auto box = pnc::md::LmpBox::from_vector(ref, "test");
  EXPECT_EQ(pnc::md::box_change(box, Eigen::Matrix3d::Identity()), "");
  Eigen::Matrix3d flat = Eigen::Matrix3d::Identity();
  flat(1, 1) = 0.0;
  EXPECT_THROW(pnc::md::box_change(box, flat), pnc::InputError);
  flat(1, 1) = -1.0; // det < 0: a reflection, not a deformation
  EXPECT_THROW(pnc::md::box_change(box, flat), pnc::InputError);
  // F not upper triangular: the box is F H rotated to the LAMMPS form, so its metric
  // (edge lengths and angles) is that of F H, and the centres are kept
  Eigen::Matrix3d G = F;
  G(2, 0) = 0.03, G(1, 0) = -0.02, G(2, 1) = 0.01;
  const std::string rcmd = pnc::md::box_change(box, G);
  const Eigen::Matrix3d Hn = edges(parse_change(ref, rcmd)), FH = G * E0;
  EXPECT_LT((Hn.transpose() * Hn - FH.transpose() * FH).cwiseAbs().maxCoeff(), 1e-10) << rcmd;
}

// The six registered cases name only what they change: the driven length (extension) or the one
// tilt (shear), so the lengths and tilts a case leaves alone keep their exact values.
TEST(MdBox, BoxChangeOfEachCaseNamesOnlyItsOwnLengthOrTilt) {
  const std::vector<double> ref = {0.0, 0.0, 0.0, 20.0, 21.0, 22.0, 0.0, 0.0, 0.0};
  const char* expect[6] = {" x final",  " y final",  " z final",
                           " yz final", " xz final", " xy final"};
  for (const auto& c : pnc::damage::deformation_cases()) {
    const std::string cmd = pnc::md::box_change(pnc::md::LmpBox::from_vector(ref, "test"),
                                                pnc::damage::deformation_gradient(c, 0.01));
    const std::string body = cmd.substr(std::string("change_box all").size());
    EXPECT_EQ(body.rfind(expect[c.driven[0]], 0), 0u) << c.id << ": " << cmd;
    int keywords = 0;
    for (const char* k : {" x ", " y ", " z ", " xy ", " xz ", " yz "})
      keywords += body.find(k) != std::string::npos;
    EXPECT_EQ(keywords, 1) << cmd;
  }
}

// A mixed case is one row (D360): the equibiaxial extension G = e_1 e_1 + e_2 e_2 at t = 0.02
// stretches x and y by the same factor 1.02 about their centres, scales every tilt by the
// stretch of its row of F (xy, xz by F11, yz by F22) and leaves z alone. The box below is
// worked out by hand from the reference box {0..20, 0..21, 0..22, xy 1.5, xz -0.5, yz 2.5}.
TEST(MdBox, EquibiaxialRowStretchesBothAxesByTheSameFactor) {
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
  g(0, 0) = g(1, 1) = 1.0;
  const pnc::damage::DeformationCase biax{
      7, "equibiaxial extension x1-x2 (x3 held)", {0, 1}, {0, 1, 2}, 0, g};
  const std::vector<double> ref = {0.0, 0.0, 0.0, 20.0, 21.0, 22.0, 1.5, -0.5, 2.5};
  const std::string cmd = pnc::md::box_change(pnc::md::LmpBox::from_vector(ref, "test"),
                                              pnc::damage::deformation_gradient(biax, 0.02));
  const Box b = parse_change(ref, cmd);
  const double tol = 1e-12;               // %.15g of lengths ~20 A
  EXPECT_NEAR(b.lo[0], -0.2, tol) << cmd; // 20 * 1.02 = 20.4 about the centre 10
  EXPECT_NEAR(b.hi[0], 20.2, tol) << cmd;
  EXPECT_NEAR(b.lo[1], -0.21, tol) << cmd; // 21 * 1.02 = 21.42 about the centre 10.5
  EXPECT_NEAR(b.hi[1], 21.21, tol) << cmd;
  EXPECT_EQ(b.lo[2], 0.0) << cmd; // z not named: kept exactly
  EXPECT_EQ(b.hi[2], 22.0) << cmd;
  EXPECT_EQ(cmd.find(" z "), std::string::npos) << cmd;
  EXPECT_NEAR(b.xy, 1.53, tol) << cmd;
  EXPECT_NEAR(b.xz, -0.51, tol) << cmd;
  EXPECT_NEAR(b.yz, 2.55, tol) << cmd;
  EXPECT_NEAR((b.hi[0] - b.lo[0]) / 20.0, (b.hi[1] - b.lo[1]) / 21.0, tol) << "same stretch";
}
