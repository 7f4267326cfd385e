// Printing the declarations of pnc/core/parameters.hpp: JSON, a commented TOML template, and
// Markdown tables (the generated key tables of the user guides, decision D232).
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace pnc {

namespace {

using json = nlohmann::json;

// A Markdown table cell: '|' escaped, one line.
std::string cell(std::string s) {
  std::string out;
  for (const char c : s) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

} // namespace

json Parameters::to_json() const {
  json secs = json::array();
  for (std::size_t s = 0; s < sections_.size(); ++s) {
    json ps = json::array();
    for (const auto& m : members_[s]) {
      if (m.is_section) continue;
      const Parameter& p = params_[m.index];
      json e = {{"name", p.path}, {"type", p.type_name()}, {"default", p.default_value},
                {"unit", p.unit}, {"text", p.text},        {"rule", p.rule()}};
      if (p.required) e["required"] = true;
      if (p.default_value.is_null() && !p.required) e["absent"] = p.absent;
      if (p.type == ParamType::integer || p.type == ParamType::integer_list)
        e["range"] = {{"min", p.int_min}, {"max", p.int_max}};
      if (p.type == ParamType::real || p.type == ParamType::real_list) {
        json r = json::object();
        if (std::isfinite(p.range.lo)) r["min"] = p.range.lo, r["min_open"] = p.range.lo_open;
        if (std::isfinite(p.range.hi)) r["max"] = p.range.hi, r["max_open"] = p.range.hi_open;
        e["range"] = r;
      }
      if (p.type == ParamType::integer_list || p.type == ParamType::real_list ||
          p.type == ParamType::string_list || p.type == ParamType::table_list) {
        e["min_size"] = p.min_size;
        if (p.max_size != std::numeric_limits<std::size_t>::max()) e["max_size"] = p.max_size;
      }
      if (!p.choices.empty()) {
        json c = json::array();
        for (const auto& ch : p.choices)
          c.push_back({{"value", ch.value}, {"meaning", ch.meaning}});
        e["allowed"] = c;
      }
      if (!p.extra_rule.empty()) e["also"] = p.extra_rule;
      if (!p.note.empty()) e["note"] = p.note;
      ps.push_back(e);
    }
    const ParamSection& sec = sections_[s];
    secs.push_back({{"path", sec.path},
                    {"text", sec.text},
                    {"applies", sec.applies},
                    {"opaque", sec.opaque},
                    {"optional", static_cast<bool>(sec.store_given)},
                    {"parameters", ps}});
  }
  return {{"title", title_}, {"sections", secs}};
}

std::string Parameters::to_toml() const {
  check_unique_paths("to_toml");
  std::string out = "# " + title_ + ": every key with its default value.\n" +
                    "# A key left out takes its default; keys marked \"no default\" are " +
                    "optional.\n";
  auto entry = [&](const Parameter& p, const std::string& c) { // c: "# " in optional sections
    std::string what = p.type_name();
    if (const std::string r = p.range_text(); !r.empty()) what += " " + r;
    if (!p.unit.empty()) what += "; unit " + p.unit;
    out += "\n# " + p.text + (p.note.empty() ? "" : "; " + p.note) + "\n# " + what + "\n";
    if (p.required)
      out += "# " + p.key() + " =   (required)\n";
    else if (p.default_value.is_null())
      out += "# " + p.key() + " =   (no default: " + p.absent + ")\n";
    else
      out += c + p.key() + " = " + toml_value(p.default_value) + "\n";
  };
  for (const auto& m : members_[0])
    if (!m.is_section) entry(params_[m.index], "");
  for (std::size_t s = 1; s < sections_.size(); ++s) {
    const ParamSection& sec = sections_[s];
    const std::string head = sec.text + (sec.applies.empty() ? "" : " (" + sec.applies + ")");
    if (sec.opaque) {
      out += "\n# [" + sec.path + "]: " + head + "; its keys are described in the user guide\n";
      continue;
    }
    const std::string c = sec.store_given ? "# " : ""; // optional: written only if wanted
    out += "\n\n# " + head + (c.empty() ? "" : " (optional: uncomment the table to give it)") +
           "\n" + c + "[" + sec.path + "]\n";
    for (const auto& m : members_[s])
      if (!m.is_section) entry(params_[m.index], c);
  }
  return out;
}

std::string Parameters::to_markdown(int heading_level) const {
  const std::string hashes(static_cast<std::size_t>(std::clamp(heading_level, 1, 6)), '#');
  std::string out;
  for (std::size_t s = 0; s < sections_.size(); ++s) {
    const ParamSection& sec = sections_[s];
    std::vector<const Parameter*> ps;
    for (const auto& m : members_[s])
      if (!m.is_section) ps.push_back(&params_[m.index]);
    if (ps.empty() && !sec.opaque) continue;
    out += (out.empty() ? "" : "\n") + hashes + " " +
           (sec.path.empty() ? std::string("Top level") : "`" + sec.path + "`") +
           (sec.applies.empty() ? "" : " (" + sec.applies + ")") + "\n\n";
    if (!sec.text.empty()) {
      std::string t = sec.text;
      t[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
      out += t + (t.back() == '.' ? "" : ".") + (sec.opaque ? "\n" : "\n\n");
    }
    if (sec.opaque) continue;
    out += "| key | type | default | range/allowed | unit | meaning |\n";
    out += "|---|---|---|---|---|---|\n";
    for (const Parameter* p : ps) {
      std::string meaning = p->text;
      if (p->default_value.is_null() && !p->required) meaning += "; absent: " + p->absent;
      if (!p->note.empty()) meaning += "; " + p->note;
      out += "| `" + p->path + "` | " + p->type_name() + " | " +
             (p->required                  ? std::string("required")
              : p->default_value.is_null() ? std::string("–")
                                           : "`" + cell(p->default_value.dump()) + "`") +
             " | " + cell(p->range_text()) + " | " + cell(p->unit) + " | " + cell(meaning) + " |\n";
    }
  }
  return out;
}

} // namespace pnc
