#pragma once
// Test helper: is a pnc run report (report.html) self-contained, and does it render in a real
// headless browser (Debian's chromium, installed by scripts/common.sh as a test dependency)?
// Link the test with ZLIB::ZLIB (the screenshot's PNG is decoded here).
#include "common/run_command.hpp"

#include "common/temp_dir.hpp" // slurp

#include <zlib.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace pnc::test {

/// What keeps a page from being self-contained: a network URL, an external src/href, a script
/// or stylesheet reference. Empty when the page stands alone.
inline std::vector<std::string> self_contained_problems(const std::string& html) {
  std::vector<std::string> p;
  for (const char* url : {"http://", "https://", "ftp://", "//cdn", "file://"})
    if (html.find(url) != std::string::npos) p.push_back(std::string("contains ") + url);
  // by hand, not std::regex: a page holds megabytes of base64 in one attribute
  std::string lower = html;
  for (auto& c : lower)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* attr : {"src=", "href="})
    for (auto i = lower.find(attr); i != std::string::npos; i = lower.find(attr, i + 1)) {
      if (i > 0 && std::isalnum(static_cast<unsigned char>(lower[i - 1]))) continue;
      std::size_t v = i + std::string(attr).size();
      if (v < lower.size() && (lower[v] == '"' || lower[v] == '\'')) ++v;
      if (lower.compare(v, 5, "data:") != 0 && lower.compare(v, 1, "#") != 0)
        p.push_back(html.substr(i, 60));
    }
  for (const char* tag : {"<script", "<link", "<iframe", "<object", "@import"})
    if (html.find(tag) != std::string::npos) p.push_back(std::string("contains ") + tag);
  return p;
}

/// Fraction of pixels of an 8-bit RGB or RGBA PNG (no interlace) that are not near-white;
/// -1 with `err` set when the file is no such PNG.
inline double ink_fraction(const std::string& png_path, std::string& err) {
  const std::string d = slurp(png_path);
  auto be32 = [&](std::size_t i) {
    return (std::uint32_t(std::uint8_t(d[i])) << 24) |
           (std::uint32_t(std::uint8_t(d[i + 1])) << 16) |
           (std::uint32_t(std::uint8_t(d[i + 2])) << 8) | std::uint32_t(std::uint8_t(d[i + 3]));
  };
  if (d.size() < 33 || d.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) {
    err = "not a PNG";
    return -1;
  }
  const std::uint32_t w = be32(16), h = be32(20);
  const int depth = std::uint8_t(d[24]), type = std::uint8_t(d[25]),
            interlace = std::uint8_t(d[28]);
  const int bpp = type == 2 ? 3 : type == 6 ? 4 : 0;
  if (depth != 8 || bpp == 0 || interlace != 0) {
    err = "unsupported PNG layout";
    return -1;
  }
  std::string idat;
  for (std::size_t i = 8; i + 12 <= d.size();) {
    const std::uint32_t len = be32(i);
    if (d.compare(i + 4, 4, "IDAT") == 0) idat += d.substr(i + 8, len);
    i += 12 + len;
  }
  const std::size_t stride = std::size_t(w) * bpp;
  std::vector<unsigned char> raw((stride + 1) * h);
  uLongf n = raw.size();
  if (uncompress(raw.data(), &n, reinterpret_cast<const Bytef*>(idat.data()), idat.size()) !=
          Z_OK ||
      n != raw.size()) {
    err = "corrupt image data";
    return -1;
  }
  std::vector<unsigned char> prev(stride, 0), cur(stride);
  std::size_t ink = 0;
  for (std::uint32_t y = 0; y < h; ++y) {
    const unsigned char f = raw[y * (stride + 1)];
    const unsigned char* in = &raw[y * (stride + 1) + 1];
    for (std::size_t x = 0; x < stride; ++x) {
      const int a = x >= std::size_t(bpp) ? cur[x - bpp] : 0, b = prev[x],
                c = x >= std::size_t(bpp) ? prev[x - bpp] : 0;
      int pred = 0;
      if (f == 1) pred = a;
      if (f == 2) pred = b;
      if (f == 3) pred = (a + b) / 2;
      if (f == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      cur[x] = static_cast<unsigned char>(in[x] + pred);
    }
    for (std::size_t x = 0; x < stride; x += bpp)
      if (cur[x] < 235 || cur[x + 1] < 235 || cur[x + 2] < 235) ++ink;
    prev.swap(cur);
  }
  return static_cast<double>(ink) / (double(w) * double(h));
}

struct BrowserResult {
  std::string error;                ///< empty when chromium ran
  std::vector<std::string> images;  ///< per <img>: "ok" (decoded, naturalWidth > 0) or "bad"
  std::vector<std::string> console; ///< console messages other than the probe's own
  double ink = -1;                  ///< non-white fraction of the 1200 x 3000 screenshot
};

/// Renders `html` in headless chromium twice: a screenshot of the page as is, and --dump-dom
/// of a copy with a probe script (added here, the page has none) that records whether every
/// image decoded. Work files go to `work_dir`. A missing chromium is an error, not a skip.
inline BrowserResult render_in_chromium(const std::string& html, const std::string& work_dir) {
  namespace fs = std::filesystem;
  BrowserResult r;
  if (run_command("command -v chromium >/dev/null 2>&1").code != 0) {
    r.error = "chromium is not installed (scripts/common.sh installs it: apt-get install chromium)";
    return r;
  }
  const std::string page = slurp(html);
  const std::string probe_path = (fs::path(work_dir) / "probe.html").string();
  std::string probed = page;
  const auto body = probed.rfind("</body>");
  if (body == std::string::npos) {
    r.error = "no </body> in " + html;
    return r;
  }
  probed.insert(body,
                "<script>window.addEventListener('load',function(){var r=[];"
                "for(var i of document.images)r.push(i.complete&&i.naturalWidth>0?'ok':'bad');"
                "document.body.setAttribute('data-pnc-images',r.join(','));"
                "console.log('pnc-probe '+r.join(','));});</script>");
  std::ofstream(probe_path, std::ios::binary) << probed;
  // a profile of its own per call: tests running in parallel never share one
  const std::string chrome = "timeout 50 chromium --headless --no-sandbox --disable-gpu "
                             "--enable-logging=stderr --v=0 --user-data-dir='" +
                             (fs::path(work_dir) / "chromium-profile").string() + "' ";
  const std::string log = (fs::path(work_dir) / "chromium.log").string();
  const CommandResult dom = run_command(chrome + "--dump-dom --virtual-time-budget=10000 'file://" +
                                        probe_path + "' 2>'" + log + "'");
  if (dom.code != 0) {
    r.error = "chromium --dump-dom failed (" + std::to_string(dom.code) + "): " + slurp(log);
    return r;
  }
  const std::string key = "data-pnc-images=\"";
  const auto at = dom.out.find(key);
  if (at == std::string::npos) {
    r.error = "the probe did not run (no data-pnc-images in the DOM)";
    return r;
  }
  const auto from = at + key.size();
  const std::string list = dom.out.substr(from, dom.out.find('"', from) - from);
  for (std::size_t s = 0; s <= list.size() && !list.empty();) {
    const auto e = list.find(',', s);
    r.images.push_back(list.substr(s, e == std::string::npos ? std::string::npos : e - s));
    if (e == std::string::npos) break;
    s = e + 1;
  }
  std::ifstream lf(log);
  for (std::string line; std::getline(lf, line);)
    if ((line.find("CONSOLE") != std::string::npos &&
         line.find("pnc-probe") == std::string::npos) ||
        line.find("Uncaught") != std::string::npos)
      r.console.push_back(line);
  const std::string shot = (fs::path(work_dir) / "screenshot.png").string();
  const CommandResult sc =
      run_command(chrome + "--screenshot='" + shot + "' --window-size=1200,3000 'file://" + html +
                  "' 2>>'" + log + "'");
  if (sc.code != 0) {
    r.error = "chromium --screenshot failed: " + slurp(log);
    return r;
  }
  std::string err;
  r.ink = ink_fraction(shot, err);
  if (r.ink < 0) r.error = "screenshot " + shot + ": " + err;
  return r;
}

} // namespace pnc::test
