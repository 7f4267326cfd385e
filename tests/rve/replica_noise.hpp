#pragma once
// Synthetic replica curves for the tests of the statistics across replicas (D12k, D417, D431):
// N replicas of NDM cases whose noise is correlated along the curve as an MD replica's is (a
// frozen structure strained step by step): per replica and component a random offset plus
// AR(1) noise with lag-1 correlation 0.9. Stresses in Pa, strains dimensionless.
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/md/statistics.hpp"
#include "pnc/rve/replicas.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace pnc::test {

struct Trial {
  rve::CombinedCases cases;
  damage::StressStrainData mean; // what the joint fit sees
};

// N replicas of cases 2 and 6 of the pure-polymer law (the tables' constants, alpha = 0.85 so
// that both modes damage within 0.12), rows 0.003 .. 0.12; noise sd 2 MPa per point (offset 1
// MPa + AR(1) 1.7 MPa, rho 0.9); `bump` Pa of a shape the law does not have, common to all.
inline Trial make_trial(int nrep, std::mt19937_64& rng, double bump,
                        const std::vector<int>& cases = {2, 6}, double noise = 1.0) {
  damage::NdmParameters p = damage::dissertation_parameters(damage::Model::pp);
  p["alpha"] = 0.85;
  std::normal_distribution<double> g(0, 1);
  const int n = 40;
  const double rho = 0.9, s_off = 1e6 * noise, s_ar = 1.7e6 * noise;
  Trial t;
  t.cases.replicas = nrep;
  t.mean.source = "<monte carlo>";
  t.mean.stress_definition = "synthetic";
  for (int id : cases) {
    rve::CombinedCase cc;
    cc.id = id;
    cc.voigt = id - 1; // 1-3: sigma11, 22, 33; 4, 5, 6: sigma23, 13, 12
    cc.strain.resize(n, 6);
    for (int k = 0; k < n; ++k)
      cc.strain.row(k) = damage::case_strain(id, 0.12 * (k + 1) / n).transpose();
    const auto truth = damage::stress_path(p, cc.strain);
    for (int r = 0; r < nrep; ++r) {
      rve::PathM y = truth;
      for (int j = 0; j < 6; ++j) {
        double ar = s_ar * g(rng);
        const double off = s_off * g(rng);
        for (int k = 0; k < n; ++k) {
          if (k > 0) ar = rho * ar + std::sqrt(1 - rho * rho) * s_ar * g(rng);
          const double x = 2.0 * k / (n - 1) - 1; // the bump: P3-like, zero at the ends
          y(k, j) += off + ar + (j == cc.voigt ? bump * (x * x * x - x) * 2.6 : 0.0);
        }
      }
      cc.replica_stress.push_back(y);
      cc.replica_stderr.push_back(rve::PathM::Constant(n, 6, 2e6));
    }
    damage::CaseCurve mc;
    mc.id = id;
    mc.strain = cc.strain;
    mc.stress = rve::PathM::Zero(n, 6);
    for (const auto& y : cc.replica_stress)
      mc.stress += y / nrep;
    // between-replica standard error of the mean, per point
    mc.stress_stderr = rve::PathM::Zero(n, 6);
    for (const auto& y : cc.replica_stress)
      mc.stress_stderr.array() += (y - mc.stress).array().square() / (nrep - 1);
    mc.stress_stderr = (mc.stress_stderr / nrep).cwiseSqrt();
    t.mean.cases.push_back(mc);
    t.cases.cases.push_back(cc);
  }
  return t;
}

} // namespace pnc::test
