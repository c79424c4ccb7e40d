// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/fabric_options.h"

#include "io/model/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace dtf::render {

namespace {

using K = FabricOption::Kind;
using R = Range;

constexpr R closed(double lo, double hi) {
  return R{lo, hi, false, false};
}
constexpr R none() { // no slider
  return R{0, 0, false, false};
}

#define DTF_FIELD(field, type)                                                                               \
  [](const FabricParams& p) { return static_cast<double>(p.field); },                                        \
      [](FabricParams& p, double v) { p.field = static_cast<type>(v); }

const std::vector<FabricOption> kOptions = {
    {"lod", "", "L", "noise voxel edge l in mm (paper Eq. 7); 0 = automatic from the pixel size", K::Number,
     closed(0, 1000), closed(0, 40), "l (mm, 0 = auto)", "%.1f", false, DTF_FIELD(lod, double)},
    {"blend-k", "k", "K", "k of Eq. 12, the weight of the input noise per iteration", K::Number,
     R{0, 1, true, false}, closed(0.01, 0.5), "k", "%.3f", true, DTF_FIELD(k, double)},
    {"frame-iterations", "", "N", "advection iterations per interactive frame (paper: 3)", K::Integer,
     closed(1, 1000), closed(1, 20), "iterations/frame", "%d", false, DTF_FIELD(iterations, int)},
    {"epsilon", "", "E", "change below which a pixel counts as converged", K::Number, closed(1e-5, 1),
     closed(0.005, 0.2), "epsilon", "%.3f", true, DTF_FIELD(epsilon, double)},
    {"blend-r", "r", "R", "r of Eq. 13, blend between the two directions", K::Number, closed(0, 1),
     closed(0, 1), "r", "%.2f", false, DTF_FIELD(r, double)},
    {"color", "colour", "MODE",
     "medical (DEC colour of the principal direction modulated by FA) | engineering (paper Eq. 13) | fibres "
     "(fibre sets: each population in its own DEC colour, strongest on top; a tensor as its principal "
     "direction only)",
     K::Choice, closed(0, 2), none(), "colour", nullptr, false,
     [](const FabricParams& p) {
       return p.colour == ColourMode::Medical ? 0.0 : p.colour == ColourMode::Engineering ? 1.0 : 2.0;
     },
     [](FabricParams& p, double v) {
       p.colour = v == 0 ? ColourMode::Medical : v == 1 ? ColourMode::Engineering : ColourMode::Fibres;
     },
     "medical engineering fibres"},
    {"look", "", "LOOK",
     "anatomy (the fabric's opacity follows FA over a grey background: --background, a DWI's mean b=0, "
     "else FA; isotropic tissue shows the anatomy) | plain (the paper's look: the fabric wherever there is "
     "tensor data) | dec-fa (no fabric: the classic DEC-FA map, |e1| x FA, medical colour, for comparison)",
     K::Choice, closed(0, 2), none(), "look", nullptr, false,
     [](const FabricParams& p) { return p.look == Look::Anatomy ? 0.0 : p.look == Look::Plain ? 1.0 : 2.0; },
     [](FabricParams& p, double v) { p.look = v == 0 ? Look::Anatomy : v == 1 ? Look::Plain : Look::DecFa; },
     "anatomy plain dec-fa"},
    {"opacity-fa-low", "", "F",
     "anatomy look: FA below which the fabric is transparent (opacity smoothstep(F, opacity-fa-high, FA))",
     K::Number, closed(0, 1), closed(0, 1), "opacity from FA", "%.2f", false, DTF_FIELD(opacityFaLow, float)},
    {"opacity-fa-high", "", "F", "anatomy look: FA from which the fabric is opaque", K::Number, closed(0, 1),
     closed(0, 1), "opaque at FA", "%.2f", false, DTF_FIELD(opacityFaHigh, float)},
    {"fibre-threshold", "fiber-threshold", "T",
     "fibre sets: drop lobes below T times their voxel's strongest (relative amplitude threshold)", K::Number,
     R{0, 1, false, true}, none(), nullptr, nullptr, false, DTF_FIELD(fibreThreshold, float)},
    {"lighting", "", "on|off", "Phong lighting of the surface", K::OnOff, closed(0, 1), none(), "lighting",
     nullptr, false, DTF_FIELD(lighting, bool)},
    {"silhouette", "", "on|off", "dark silhouette edges", K::OnOff, closed(0, 1), none(), "silhouette",
     nullptr, false, DTF_FIELD(silhouette, bool)},
    {"sharpen", "", "W", "unsharp-mask weight of the texture", K::Number, closed(0, 4), closed(0, 1),
     "sharpen", "%.2f", false, DTF_FIELD(sharpen, double)},
    {"depth-color", "depth-colour", "W", "weight of depth cueing in the colour", K::Number, closed(0, 1),
     closed(0, 1), "depth colour", "%.2f", false, DTF_FIELD(depthColour, double)},
    {"contrast", "", "C", "stretch of the texture before colouring; 1 = raw", K::Number, closed(0.1, 100),
     closed(1, 8), "contrast", "%.1f", false, DTF_FIELD(contrast, double)},
    {"step", "", "PX", "advection step in pixels", K::Number, R{0, 16, true, false}, closed(0.5, 4),
     "step (px)", "%.2f", false, DTF_FIELD(stepPixels, double)},
    {"fade-out-of-plane", "fade", "W", "fade the texture where the principal direction leaves the surface",
     K::Number, closed(0, 1), closed(0, 1), "fade out-of-plane", "%.2f", false,
     DTF_FIELD(fadeOutOfPlane, float)},
    {"iterations", "", "N", "advection iterations of a still image at most (stops earlier once converged)",
     K::Integer, closed(0, 10000), none(), nullptr, nullptr, false, DTF_FIELD(stillMaxIterations, int)},
    {"auto-lod-pixels", "", "PX", "pixels one noise tile spans when l is automatic", K::Number,
     closed(8, 4096), none(), nullptr, nullptr, false, DTF_FIELD(autoLodPixels, double)},
    {"seed", "", "S", "reaction-diffusion noise seed", K::Integer, closed(0, 2147483647), none(), nullptr,
     nullptr, false, DTF_FIELD(seed, std::uint32_t)},
    {"fray", "", "W",
     "with --uncertainty: each noise cell turns the threads by a random angle of up to W times the voxel's 95 % "
     "cone of uncertainty (0 = no fraying)",
     K::Number, closed(0, 4), closed(0, 2), "fray", "%.2f", false, DTF_FIELD(fray, double)},
    {"fray-cells", "", "N", "with --uncertainty: noise cells per noise tile edge, each turned by its own angle",
     K::Number, closed(1, 256), none(), nullptr, nullptr, false, DTF_FIELD(frayCells, double)},
    {"fa-floor", "", "F", "the fabric only where FA >= F (elsewhere the background or grey)", K::Number,
     R{0, 1, false, true}, none(), nullptr, nullptr, false, DTF_FIELD(faFloor, float)},
};

#undef DTF_FIELD

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

} // namespace

bool FabricOption::matches(const std::string& key) const {
  if (key == name) return true;
  std::istringstream in(aliases);
  std::string a;
  while (in >> a)
    if (a == key) return true;
  return false;
}

double FabricOption::parse(const std::string& text) const {
  const std::string n = name;
  if (kind == Kind::OnOff) {
    if (text == "on") return 1;
    if (text == "off") return 0;
    throw UsageError(n + " takes on or off, got '" + text + "'");
  }
  if (kind == Kind::Choice) {
    const auto names = choiceNames();
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (text == names[i] || (names[i] == "fibres" && text == "fibers")) return static_cast<double>(i);
      list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    }
    throw UsageError(n + " takes " + list + ", got '" + text + "'");
  }
  const char* s = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (text.empty() || end == s || *end != '\0' || !std::isfinite(v))
    throw UsageError(n + " takes a number, got '" + text + "'");
  if (kind == Kind::Integer && v != std::floor(v))
    throw UsageError(n + " takes an integer, got '" + text + "'");
  if (!range.contains(v)) throw UsageError(n + " must lie in " + range.text() + ", got " + text);
  return v;
}

std::vector<std::string> FabricOption::choiceNames() const {
  std::vector<std::string> names;
  std::istringstream in(choices ? choices : "");
  for (std::string a; in >> a;)
    names.push_back(a);
  return names;
}

std::string FabricOption::cliSynopsis() const {
  if (kind == Kind::OnOff) return std::string("--no-") + name;
  return std::string("--") + name + " " + metavar;
}

const std::vector<FabricOption>& fabricOptions() {
  return kOptions;
}

const FabricOption* findFabricOption(const std::string& key) {
  for (const auto& o : kOptions)
    if (o.matches(key)) return &o;
  return nullptr;
}

std::string formatFabricValue(const FabricOption& o, double v) {
  if (o.kind == FabricOption::Kind::OnOff) return v != 0 ? "on" : "off";
  if (o.kind == FabricOption::Kind::Choice) {
    const auto names = o.choiceNames();
    const auto i = static_cast<std::size_t>(v);
    return i < names.size() ? names[i] : number(v);
  }
  return number(v);
}

} // namespace dtf::render
