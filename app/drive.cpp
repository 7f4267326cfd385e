// The point driver (docs/drive.md; docs/decisions.md D167 Newton on mixed control, D168
// energy account). Every stress, state and tangent comes from the plugin's C ABI through
// pnc::fe_material::Material: the driver tests what finite-element hosts get.
#include "drive.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace pnc::app {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
// The small-strain range the path file allows (drive_path.cpp); a stress target that needs
// more is refused rather than driven into meaningless strains.
constexpr double kStrainLimit = 1.0;
using Mat6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Vec6 vec(const std::array<double, 6>& a) {
  return Eigen::Map<const Vec6>(a.data());
}

// The secant stiffness C0 + C1(D) of a state: the tangent of a zero increment at zero
// strain, where no damage mode can be loading (theory.md 1.4), so the plugin returns it.
Mat6 secant(const pnc::fe_material::Material& m, const std::vector<double>& s) {
  std::vector<double> s1(s.size());
  const std::array<double, 6> zero{};
  std::array<double, 6> sig{};
  std::array<double, 36> K{};
  m.integrate(s.data(), s1.data(), zero.data(), zero.data(), sig.data(), K.data());
  return Eigen::Map<const Mat6>(K.data());
}

struct Point {
  Vec6 eps = Vec6::Zero(), sig = Vec6::Zero();
  std::vector<double> state;
  Mat6 K = Mat6::Zero();
};

// One step: strain-controlled components set, stress-controlled ones solved by Newton with
// the consistent tangent, starting from a predictor with the previous tangent. Returns an
// empty string on success, else the reason.
std::string solve_step(const pnc::fe_material::Material& m, const Point& p0,
                       const std::array<char, 6>& kind, const Vec6& target, double tol,
                       int max_iter, Point& p1, int& iterations, double& residual) {
  std::vector<int> S, E;
  for (int i = 0; i < 6; ++i)
    (kind[static_cast<std::size_t>(i)] == 's' ? S : E).push_back(i);
  const int ns = static_cast<int>(S.size());
  Vec6 eps = p0.eps;
  for (int i : E)
    eps[i] = target[i];
  auto solve_ss = [&](const Mat6& K, const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    Eigen::MatrixXd Kss(ns, ns);
    for (int a = 0; a < ns; ++a)
      for (int b = 0; b < ns; ++b)
        Kss(a, b) = K(S[a], S[b]);
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Kss);
    if (!lu.isInvertible()) return false;
    x = lu.solve(rhs);
    return x.allFinite();
  };
  if (ns > 0) { // predictor: K_SS d eps_S = (target_S - sig_S) - K_SE d eps_E
    Eigen::VectorXd rhs(ns), x;
    const Vec6 de = eps - p0.eps;
    for (int a = 0; a < ns; ++a) {
      rhs[a] = target[S[a]] - p0.sig[S[a]];
      for (int i : E)
        rhs[a] -= p0.K(S[a], i) * de[i];
    }
    if (solve_ss(p0.K, rhs, x))
      for (int a = 0; a < ns; ++a)
        eps[S[a]] += x[a];
  }
  p1.state.resize(p0.state.size());
  std::array<double, 6> e0{}, de{}, sig{};
  std::array<double, 36> K{};
  for (iterations = 0;; ++iterations) {
    for (int i = 0; i < 6; ++i) {
      e0[static_cast<std::size_t>(i)] = p0.eps[i];
      de[static_cast<std::size_t>(i)] = eps[i] - p0.eps[i];
    }
    char err[512] = {0};
    const int st = m.try_integrate(p0.state.data(), p1.state.data(), e0.data(), de.data(),
                                   sig.data(), K.data(), err, sizeof err);
    if (st != PNC_MATERIAL_OK) return std::string("the plugin refused the increment: ") + err;
    p1.sig = vec(sig);
    p1.K = Eigen::Map<const Mat6>(K.data());
    residual = 0;
    Eigen::VectorXd r(ns);
    for (int a = 0; a < ns; ++a) {
      r[a] = p1.sig[S[a]] - target[S[a]];
      residual = std::max(residual, std::abs(r[a]));
    }
    if (residual <= tol) break;
    if ((eps.cwiseAbs().array() > kStrainLimit).any())
      return fmt::format("the stress targets need a strain beyond the small-strain range of the "
                         "law (|strain| <= {}; max |strain| {:.3g} in the Newton iterates): "
                         "the targets exceed what the material carries",
                         kStrainLimit, eps.cwiseAbs().maxCoeff());
    if (iterations >= max_iter)
      return fmt::format("Newton did not converge in {} iterations: residual {:.3g} Pa > "
                         "tolerance {:.3g} Pa (a stress-controlled path past the stress peak has "
                         "no solution; drive that part in strain)",
                         max_iter, residual, tol);
    Eigen::VectorXd x;
    if (!solve_ss(p1.K, r, x)) return "the tangent of the stress-controlled components is singular";
    for (int a = 0; a < ns; ++a)
      eps[S[a]] -= x[a];
  }
  if ((eps.cwiseAbs().array() > kStrainLimit).any())
    return fmt::format("the stress targets need a strain beyond the small-strain range of the "
                       "law (|strain| <= {}; max |strain| {:.3g})",
                       kStrainLimit, eps.cwiseAbs().maxCoeff());
  p1.eps = eps;
  return {};
}

} // namespace

pnc::fe_material::Material driven_material(const pnc::fe_material::Plugin& plugin,
                                           const pnc::fe_material::Material& card,
                                           const DrivePath& path) {
  const auto Rc = card.rotation();
  std::array<double, 9> R{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        R[static_cast<std::size_t>(3 * i + j)] +=
            Rc[static_cast<std::size_t>(3 * i + k)] *
            path.rotation[static_cast<std::size_t>(3 * k + j)];
  return plugin.from_constants(card.model(), card.constants(), &R);
}

DriveResult drive(const pnc::fe_material::Material& m, const DrivePath& path) {
  DriveResult res;
  res.state_names = m.state_names();
  Point p;
  p.state = m.initial_state();
  p.K = secant(m, p.state);
  Mat6 Csec = p.K; // secant of the current state
  res.residual_tolerance = path.newton_strain_tol * p.K.cwiseAbs().maxCoeff();

  auto record = [&](int step, int seg, const Point& q, int iters, double resid,
                    const DriveRecord* prev, const Mat6& C_old, const Mat6& C_new) {
    DriveRecord r;
    r.step = step;
    r.segment = seg;
    for (int i = 0; i < 6; ++i) {
      r.strain[static_cast<std::size_t>(i)] = q.eps[i];
      r.stress[static_cast<std::size_t>(i)] = q.sig[i];
    }
    r.state = q.state;
    Eigen::Map<Mat6>(r.tangent.data()) = q.K;
    r.stored = 0.5 * q.sig.dot(q.eps);
    if (prev) {
      const Vec6 e0 = vec(prev->strain), s0 = vec(prev->stress);
      r.work = prev->work + 0.5 * (s0 + q.sig).dot(q.eps - e0);
      // -1/2 eps.dC.eps with dC = C_new - C_old (C1 is linear in D), trapezoidal in the
      // strain: the dissipation of the damage growth over the step (D168)
      const Mat6 dC = C_new - C_old;
      r.dissipated = prev->dissipated - 0.25 * (e0.dot(dC * e0) + q.eps.dot(dC * q.eps));
    }
    r.newton_iterations = iters;
    r.newton_residual = resid;
    res.max_newton_iterations = std::max(res.max_newton_iterations, iters);
    res.rows.push_back(std::move(r));
  };
  record(0, 0, p, 0, 0.0, nullptr, Csec, Csec);

  int step = 0;
  for (std::size_t g = 0; g < path.segments.size(); ++g) {
    const DriveSegment& seg = path.segments[g];
    Vec6 start;
    for (int i = 0; i < 6; ++i) {
      const bool s = seg.kind[static_cast<std::size_t>(i)] == 's';
      res.mixed = res.mixed || s;
      start[i] = s ? p.sig[i] : p.eps[i];
    }
    const Vec6 end = vec(seg.target);
    for (int j = 1; j <= seg.steps; ++j) {
      ++step;
      const Vec6 target = start + (end - start) * (static_cast<double>(j) / seg.steps);
      Point q;
      int iters = 0;
      double resid = 0;
      const std::string why = solve_step(m, p, seg.kind, target, res.residual_tolerance,
                                         path.newton_max_iterations, q, iters, resid);
      if (!why.empty()) {
        res.converged = false;
        res.failure =
            fmt::format("{}: segment[{}]{} step {} (path step {}): {}", path.source, g + 1,
                        seg.label.empty() ? "" : " '" + seg.label + "'", j, step, why);
        return res;
      }
      const Mat6 Cnew = q.state == p.state ? Csec : secant(m, q.state);
      record(step, static_cast<int>(g + 1), q, iters, resid, &res.rows.back(), Csec, Cnew);
      Csec = Cnew;
      p = std::move(q);
    }
  }
  return res;
}

} // namespace pnc::app
