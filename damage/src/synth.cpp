#include "pnc/damage/synth.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/reference.hpp"

#include <algorithm>
#include <random>
#include <sstream>

namespace pnc::damage {

void SynthOptions::validate() const {
  const std::string src = "<synth options>";
  if (points < 3) fail(src, "points", std::to_string(points), "must be >= 3");
  if (!(max_extension > 0 && max_extension < 1))
    fail(src, "max_extension", std::to_string(max_extension), "must be in (0, 1)");
  if (!(max_shear > 0 && max_shear < 2))
    fail(src, "max_shear", std::to_string(max_shear), "must be in (0, 2)");
  if (!(noise_sd >= 0)) fail(src, "noise_sd", std::to_string(noise_sd), "must be >= 0");
  for (int c : cases)
    deformation_case(c, src + ": field 'cases'");
}

StressStrainData synthesize(const NdmParameters& p, const SynthOptions& o) {
  o.validate();
  const std::vector<int> ids = o.cases.empty() ? model_cases(p.model) : o.cases;
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  StressStrainData d;
  std::ostringstream def;
  def << "synthetic: NDM " << model_name(p.model) << " + Gaussian noise sd " << o.noise_sd / 1e6
      << " MPa, seed " << o.seed;
  d.stress_definition = def.str();
  d.source = "<synthetic>";
  for (int id : ids) {
    const DeformationCase& dc = deformation_case(id);
    // extension range when every driven component is a normal strain (D360)
    const bool extension = is_extension(dc);
    const double top = extension ? o.max_extension : o.max_shear;
    CaseCurve c;
    c.id = id;
    c.strain.resize(o.points, 6);
    for (int i = 0; i < o.points; ++i)
      c.strain.row(i) = case_strain(id, top * (i + 1) / o.points).transpose();
    c.stress = stress_path(p, c.strain);
    for (Eigen::Index i = 0; i < c.stress.rows(); ++i)
      for (int j = 0; j < 6; ++j)
        c.stress(i, j) += o.noise_sd * noise(rng);
    if (o.noise_sd > 0) c.stress_stderr = PathMatrix::Constant(o.points, 6, o.noise_sd);
    d.cases.push_back(std::move(c));
  }
  return d;
}

} // namespace pnc::damage
