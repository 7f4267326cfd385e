// The one progress/ETA line (pnc/core/progress.hpp, D344, D345).
#include "pnc/core/progress.hpp"

#include "pnc/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <utility>

namespace pnc {

namespace {

double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Counts as integers ("3/5"), other amounts with 4 significant digits ("2.4e-05").
std::string amount(double v, bool whole) {
  return whole ? fmt::format("{:.0f}", v) : fmt::format("{:.4g}", v);
}

bool is_whole(double v) {
  return std::fabs(v) < 1e15 && v == std::floor(v);
}

void check_amount(double v, const char* field) {
  if (!std::isfinite(v) || v < 0)
    fail("<progress>", field, fmt::format("{}", v), "must be finite and >= 0");
}

} // namespace

std::string format_duration(double s) {
  if (!std::isfinite(s)) return "unknown";
  s = std::max(s, 0.0);
  if (s < 9.95) return fmt::format("{:.1f} s", s);
  const long long n = std::llround(s);
  if (n < 60) return fmt::format("{} s", n);
  if (n < 3600) return fmt::format("{} min {:02d} s", n / 60, static_cast<int>(n % 60));
  const long long m = std::llround(s / 60);
  return fmt::format("{} h {:02d} min", m / 60, static_cast<int>(m % 60));
}

std::string format_progress(const ProgressState& s) {
  const bool whole = is_whole(s.done) && is_whole(s.total);
  const double pct = s.total > 0 ? 100 * s.done / s.total : 100.0;
  std::string line = fmt::format("{}: {}/{} {} ({:.1f}%), elapsed {}, ETA {}", s.what,
                                 amount(s.done, whole), amount(s.total, whole), s.unit, pct,
                                 format_duration(s.elapsed_s), format_duration(s.eta_s));
  if (!s.detail.empty()) line += "; " + s.detail;
  return line;
}

void print_progress(const ProgressState& s) {
  std::cerr << format_progress(s) + "\n" << std::flush; // one write: whole lines in pnc.log
}

Progress::Progress(std::string what, double total, std::string unit, ProgressOptions o)
    : what_(std::move(what)), unit_(std::move(unit)), total_(total), o_(std::move(o)) {
  check_amount(total, "total");
  if (!(o_.every_s >= 0) || !std::isfinite(o_.every_s))
    fail("<progress>", "every_s", fmt::format("{}", o_.every_s), "must be finite and >= 0");
  if (o_.lanes < 1) fail("<progress>", "lanes", std::to_string(o_.lanes), "must be >= 1");
  t0_ = last_line_ = now();
}

double Progress::now() const {
  return o_.clock ? o_.clock() : steady_seconds();
}

double Progress::elapsed_s() const {
  return now() - t0_;
}

double Progress::eta_s() const {
  const double left = std::max(total_ - done_, 0.0);
  if (left == 0) return 0.0;
  const double worked = done_ - reused_, el = elapsed_s();
  if (worked <= 0 || el <= 0) return std::nan(""); // no rate measured yet (D345)
  if (o_.lanes == 1) return el / worked * left;
  // rounds of `lanes` units that end together: time per round x rounds left (D345)
  const double lanes = o_.lanes;
  return el / std::ceil(worked / lanes) * std::ceil(left / lanes);
}

ProgressState Progress::state(const std::string& detail) const {
  return {what_, unit_, done_, total_, elapsed_s(), eta_s(), detail};
}

bool Progress::add(double amount, bool reused, const std::string& detail) {
  check_amount(amount, "amount");
  done_ += amount;
  if (reused) reused_ += amount;
  if (!o_.enabled) return false;
  const double t = now();
  const bool complete = done_ >= total_;
  const bool due = t - last_line_ >= o_.every_s;
  if (!(due || (complete && !printed_complete_))) return false;
  last_line_ = t;
  printed_complete_ = printed_complete_ || complete;
  const ProgressState s = state(detail);
  if (o_.sink)
    o_.sink(s);
  else
    print_progress(s);
  return true;
}

bool Progress::advance(double amount, const std::string& detail) {
  return add(amount, false, detail);
}

bool Progress::set(double done, const std::string& detail) {
  if (!(done >= done_))
    fail("<progress>", "done", fmt::format("{}", done),
         fmt::format("must not be below the work already done ({})", done_));
  return add(done - done_, false, detail);
}

bool Progress::skip(double amount, const std::string& detail) {
  return add(amount, true, detail);
}

Phase::Phase(std::string what, const std::string& doing, bool enabled,
             std::function<void(const std::string&)> print, ProgressClock clock)
    : what_(std::move(what)), enabled_(enabled), print_(std::move(print)),
      clock_(std::move(clock)) {
  t0_ = clock_ ? clock_() : steady_seconds();
  if (!print_) print_ = [](const std::string& line) { std::cerr << line + "\n" << std::flush; };
  if (enabled_) print_(fmt::format("{}: {} ...", what_, doing));
}

double Phase::seconds() const {
  return (clock_ ? clock_() : steady_seconds()) - t0_;
}

void Phase::done(const std::string& result) {
  if (finished_) return;
  finished_ = true;
  if (enabled_) print_(fmt::format("{}: {} in {}", what_, result, format_duration(seconds())));
}

} // namespace pnc
