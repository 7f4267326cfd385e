// The in-process side of pnc::md::Lammps (runner.hpp): opening an instance without MPI, typed
// settings, globals and per-atom arrays, fix scalars and the fix-external callback. The one
// place besides the rest of md/ that calls the LAMMPS C API for the ESCM coupler (D346).
#include "pnc/core/error.hpp"
#include "pnc/md/runner.hpp"

#include <lammps/library.h>

#include <stdexcept>

namespace pnc::md {

namespace {
// LAMMPS calls this with the pointer set_external_force registered: the caller's callback.
// The callback runs inside LAMMPS's C code, which an exception must not cross (noexcept:
// one that escapes ends the process instead of unwinding through LAMMPS).
void external_trampoline(void* p, Step step, int n, AtomId* id, double** x,
                         double** fext) noexcept {
  (*static_cast<ExternalForce*>(p))(step, n, id, x, fext);
}

void check_id_size(void* h, const char* doing) {
  if (lammps_extract_setting(h, "tagint") != static_cast<int>(sizeof(AtomId)))
    fail_tool("LAMMPS", doing, "this LAMMPS build's atom id size differs from pnc's", "");
}
} // namespace

std::unique_ptr<Lammps> Lammps::open_in_process(const std::vector<std::string>& args,
                                                const std::string& doing) {
  std::vector<std::string> a = args;
  std::vector<char*> argv;
  for (auto& s : a)
    argv.push_back(s.data());
  void* h = lammps_open_no_mpi(static_cast<int>(argv.size()), argv.data(), nullptr);
  if (!h) fail_tool("LAMMPS", doing, "lammps_open returned no instance", "");
  auto l = std::make_unique<Lammps>(h);
  l->owned_ = true;
  return l;
}

void* Lammps::local(const char* what) const {
  if (fd_ >= 0 || !h_)
    throw std::logic_error(std::string("pnc::md::Lammps::") + what +
                           " needs an in-process LAMMPS instance");
  return h_;
}

int Lammps::extract_setting(const std::string& name) {
  const int v = lammps_extract_setting(local("extract_setting"), name.c_str());
  if (v < 0) fail("<lammps>", "setting", name, "LAMMPS has no integer setting of that name");
  return v;
}

std::string Lammps::extract_global_string(const std::string& name) {
  void* h = local("extract_global_string");
  const char* s = lammps_extract_global_datatype(h, name.c_str()) == LAMMPS_STRING
                      ? static_cast<const char*>(lammps_extract_global(h, name.c_str()))
                      : nullptr;
  if (!s) fail("<lammps>", "global", name, "LAMMPS has no global string of that name");
  return s;
}

std::array<bool, 3> Lammps::periodic() {
  LmpBox b;
  int per[3];
  int changed;
  lammps_extract_box(local("periodic"), b.lo.data(), b.hi.data(), &b.xy, &b.yz, &b.xz, per,
                     &changed);
  return {per[0] != 0, per[1] != 0, per[2] != 0};
}

std::vector<AtomId> Lammps::gather_ids() {
  void* h = local("gather_ids");
  check_id_size(h, "gathering the atom ids");
  std::vector<AtomId> ids(static_cast<std::size_t>(lammps_get_natoms(h)));
  std::string name = "id";
  lammps_gather_atoms(h, name.data(), 0, 1, ids.data());
  return ids;
}

LocalAtoms Lammps::local_atoms() {
  void* h = local("local_atoms");
  check_id_size(h, "reading the local atoms");
  LocalAtoms a;
  a.n = lammps_extract_setting(h, "nlocal");
  a.id = static_cast<const AtomId*>(lammps_extract_atom(h, "id"));
  a.x = static_cast<double**>(lammps_extract_atom(h, "x"));
  a.v = static_cast<double**>(lammps_extract_atom(h, "v"));
  a.f = static_cast<double**>(lammps_extract_atom(h, "f"));
  if (a.n > 0 && (!a.id || !a.x || !a.v || !a.f))
    fail_tool("LAMMPS", "reading the local atoms", "a per-atom array id, x, v or f is missing", "");
  return a;
}

double Lammps::fix_scalar(const std::string& id) {
  auto* p = static_cast<double*>(
      lammps_extract_fix(local("fix_scalar"), id.c_str(), LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR, 0, 0));
  if (!p) fail("<lammps>", "fix " + id, "", "no global scalar");
  const double v = *p;
  lammps_free(p);
  return v;
}

void Lammps::set_external_force(const std::string& fix_id, ExternalForce cb) {
  void* h = local("set_external_force");
  if (!lammps_has_id(h, "fix", fix_id.c_str()))
    fail("<lammps>", "fix", fix_id,
         "no fix of that id (define `fix ID group external pf/callback N M` first)");
  auto& slot = external_[fix_id];
  slot = std::make_unique<ExternalForce>(std::move(cb));
  lammps_set_fix_external_callback(h, fix_id.c_str(), &external_trampoline, slot.get());
}

} // namespace pnc::md
