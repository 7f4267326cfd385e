#pragma once
// The opaque pnc_material of the C ABI (pnc/fe_material/pnc_material.h) and its derived
// properties (ABI 1.1, docs/plugin.md "Properties"). Internal to the plugin.
#include "pnc/damage/ndm.hpp"

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

namespace pnc::fe_material::detail {

/// One scalar property: name, units ("Pa" or "1") and value.
struct Property {
  std::string name;
  const char* units;
  double value;
};

/// Every property of a prepared law (global frame), in the documented order:
/// elastic_stiffness_IJ, damage_stiffness_K_IJ, n_damage_modes, critical_stretch,
/// damage_onset_stretch, p_wave_modulus_max, youngs_modulus_I, shear_modulus_23/13/12,
/// poisson_ratio_12/13/23/21/31/32.
std::vector<Property> make_properties(const pnc::damage::PreparedNdm& q);

/// max over unit n of the largest eigenvalue of the acoustic tensor
/// Gamma_ik(n) = C_ijkl n_j n_l of an engineering-Voigt stiffness C (units of C): the largest
/// P-wave (longitudinal) modulus over all propagation directions.
double max_p_wave_modulus(const pnc::damage::Matrix6& C);

} // namespace pnc::fe_material::detail

struct pnc_material {
  pnc::damage::PreparedNdm kernel; ///< the parameters (kernel.p), prepared once at creation
  std::string source;              ///< card path or "<constants>", for messages
  std::string verdict = "usable";  ///< the card's verdict level

  /// The properties, computed at the first query (the P-wave search costs ~1e4 eigen
  /// solves, which a host that never asks should not pay); thread-safe (double-checked
  /// locking: std::call_once would make the plugin depend on ld-linux through libstdc++'s
  /// thread-local once state, which D154 does not allow).
  const std::vector<pnc::fe_material::detail::Property>& properties() const {
    if (!properties_ready_.load(std::memory_order_acquire)) {
      const std::lock_guard<std::mutex> lock(properties_mutex_);
      if (!properties_ready_.load(std::memory_order_relaxed)) {
        properties_ = pnc::fe_material::detail::make_properties(kernel);
        properties_ready_.store(true, std::memory_order_release);
      }
    }
    return properties_;
  }

private:
  mutable std::mutex properties_mutex_;
  mutable std::atomic<bool> properties_ready_{false};
  mutable std::vector<pnc::fe_material::detail::Property> properties_;
};
