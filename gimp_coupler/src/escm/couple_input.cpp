// The input of `pnc gimp couple` (JSON or TOML, D357) (couple_input.hpp, docs/escm.md "Input
// file"): read through the declarations of couple_parameters.cpp, then the rules between keys.
#include "couple_input.hpp"

#include "md_region.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/run_dir.hpp"

#include <nlohmann/json.hpp>

#include <set>

namespace pnc::gimp::escm {

namespace {

using json = nlohmann::json;

/// One level of the input (the top, or "short" with `prefix` "short") read through the
/// declarations (couple_parameters.cpp) into `p`: only the keys given change `p`. "crack":
/// false turns the crack off (taken out before read(), which reads tables), a table turns it on.
void read_level(const json& level, CoupleInput& p, const std::string& src, bool top,
                const std::string& prefix) {
  json j = level;
  int crack = -1; // -1: not given, 0: false, 1: a table (read() then sets crack_given)
  if (j.is_object() && j.contains("crack")) {
    const json& c = j.at("crack");
    if (c.is_boolean() && !c.get<bool>()) {
      crack = 0;
      j.erase("crack");
    } else if (c.is_object()) {
      crack = 1;
    } else {
      fail(src, prefix.empty() ? "crack" : prefix + ".crack", show_json(c),
           "must be an object (or false)");
    }
  }
  Parameters decl(top ? "pnc gimp couple input" : "pnc gimp couple input, short");
  bool crack_given = false;
  declare_couple_input(decl, p, top, crack_given);
  const json out = decl.read(j, src, prefix);
  if (crack >= 0) p.crack = crack_given;
  if (top && p.lj_given) {
    if (!out.at("lj").contains("cutoff")) p.rc = 2.5 * p.sig;
    if (p.rc < 1.2 * p.sig || p.rc > 6 * p.sig)
      fail(src, "lj.cutoff", std::to_string(p.rc), "must be in [1.2, 6] sigma");
  }
}

/// Cases II/III (D80, D81): the crack line runs along the cell boundary through the centre of
/// the block, between two atom rows, and the pre-crack ends before the block.
void check_crack(const CoupleInput& p, const std::string& src) {
  if (p.load == "tension_x")
    fail(src, "load", "\"tension_x\"",
         "a crack along x needs load \"tension_y\" (Case II) or \"shear\" (Case III)");
  if (p.nby % 2 != 0)
    fail(src, "block_cells", std::to_string(p.nby),
         "with a crack the block needs an even number of cell rows (the crack line is the cell "
         "boundary through its centre, between two atom rows, D80)");
  if ((p.ncy - p.nby) % 2 != 0)
    fail(src, "cells", std::to_string(p.ncy),
         "with a crack cells[1] - block_cells[1] must be even (block centred on the crack line)");
  const int bx0 = (p.ncx - p.nbx) / 2;
  if (p.crack_cells > bx0 - 1)
    fail(src, "crack.length_cells", std::to_string(p.crack_cells),
         "the pre-crack tip must lie at least one cell before the atom block (<= " +
             std::to_string(bx0 - 1) + " here, D81)");
}

} // namespace

CoupleInput read_couple_input(const std::string& src, bool short_mode) {
  const json j = read_input_file(src, "a couple input file", "input"); // D357
  if (!j.is_object()) fail(src, "", "", "the input must be a JSON object");
  CoupleInput p;
  read_level(j, p, src, true, "");
  if (short_mode && j.contains("short")) {
    if (!j.at("short").is_object())
      fail(src, "short", show_json(j.at("short")), "must be an object");
    read_level(j.at("short"), p, src, false, "short");
  }
  const int rings = p.svc + p.ivc;
  if (p.nbx < 2 * rings + 1 || p.nby < 2 * rings + 1)
    fail(src, "block_cells", std::to_string(p.nbx) + " x " + std::to_string(p.nby),
         "must be at least 2 (svc_rings + ivc_rings) + 1 cells per axis");
  if (p.nbx + 4 > p.ncx || p.nby + 4 > p.ncy)
    fail(src, "cells", std::to_string(p.ncx) + " x " + std::to_string(p.ncy),
         "the continuum needs >= 2 cells around the atom block on each side");
  if (p.crack) check_crack(p, src);
  make_md_region(p.md_type, src)->check_input(p, src); // the region kind's own rules
  return p;
}

std::string read_input_as_json_text(const std::string& path) {
  return read_input_file(path, "a couple input file", "input").dump(); // D357
}

/// except `checkpoint_every_ps` and `comment` (top level and in "short"). The error names the
/// input file and the first key that differs.
void check_same_input(const std::string& src, const std::string& stored, const std::string& now,
                      const std::string& ckpt) {
  auto clean = [](json j) {
    if (!j.is_object()) return j;
    j.erase("comment");
    j.erase("checkpoint_every_ps");
    if (j.contains("short") && j["short"].is_object()) {
      j["short"].erase("comment");
      j["short"].erase("checkpoint_every_ps");
    }
    return j;
  };
  json a, b;
  try {
    a = clean(parse_json(stored, ckpt));
  } catch (const std::exception&) {
    fail(ckpt, "/run/input", "", "the stored input is not valid JSON");
  }
  b = clean(parse_json(now, src));
  require_same_input(src, a, b, ckpt, "checkpoint_every_ps and comment"); // D339
}

} // namespace pnc::gimp::escm
