// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewer/view_script.h"

#include "io/formats/atomic_file.h"
#include "io/formats/fibre_io.h"
#include "io/formats/formats.h"
#include "io/formats/movie_writer.h"
#include "io/formats/tensor_io.h"
#include "io/model/error.h"
#include "render/fabric_options.h"
#include "surfaces/slices.h"
#include "surfaces/tracking/tracking_parameters.h"
#include "ui/session/file_kinds.h"
#include "ui/session/surface_spec.h"
#include "ui/session/tensor_input.h"
#include "ui/session/track_request.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

namespace dtf::app {

namespace {

struct LineError {
  std::string message;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\v\f"); // all that words() splits on
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\v\f");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> w;
  std::istringstream in(s);
  for (std::string t; in >> t;)
    w.push_back(t);
  return w;
}

double number(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw LineError{what + ": '" + text + "' is not a number"};
  return v;
}

int integer(const std::string& text, const std::string& what) {
  const double v = number(text, what);
  if (v != std::floor(v) || std::abs(v) > 1e9) throw LineError{what + ": '" + text + "' is not an integer"};
  return static_cast<int>(v);
}

bool onOff(const std::string& text, const std::string& what) {
  if (text == "on" || text == "1" || text == "true") return true;
  if (text == "off" || text == "0" || text == "false") return false;
  throw LineError{what + " takes on or off, got '" + text + "'"};
}

void expectArgs(const std::vector<std::string>& w, std::size_t n, const char* usage) {
  if (w.size() != n + 1) throw LineError{std::string("usage: ") + usage};
}

// `set NAME VALUE`: any option of render/fabric_options.h by its name or an older script name.
ScriptSetParam parseParam(const std::string& name, const std::string& value) {
  const render::FabricOption* o = render::findFabricOption(name);
  if (!o) {
    std::string names;
    for (const auto& f : render::fabricOptions())
      names += (names.empty() ? "" : ", ") + std::string(f.name);
    throw LineError{"unknown fabric parameter '" + name + "' (" + names + ")"};
  }
  const std::string text = o->kind == render::FabricOption::Kind::OnOff ? (onOff(value, name) ? "on" : "off")
                                                                         : value;
  try {
    return {o->name, o->parse(text)};
  } catch (const UsageError& e) {
    // The message names the option as the line does (an older name stays an older name).
    const std::string what = e.what(), canonical = o->name;
    throw LineError{what.rfind(canonical, 0) == 0 ? name + what.substr(canonical.size()) : what};
  }
}

// `track KEY=VALUE ...`: the options of `dtfabric track` (see view_script.h).
session::TrackRequest parseTrack(const std::vector<std::string>& w) {
  session::TrackRequest r;
  r.seeds = session::SeedKind::Surface; // the surface on screen
  bool counted = false;
  for (std::size_t i = 1; i < w.size(); ++i) {
    const std::string& a = w[i];
    if (a == "rk4" || a == "euler") {
      r.options.rk4 = a == "rk4";
      continue;
    }
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq + 1 == a.size())
      throw LineError{"track: expected KEY=VALUE, got '" + a + "'"};
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    auto setCount = [&](session::SeedCount kind) {
      if (counted) throw LineError{"track: give one of select=, seeds=, per-voxel="};
      counted = true;
      r.count = kind;
      r.number = integer(value, "track " + key);
      if (r.number < 1 || r.number > 10'000'000) throw LineError{"track " + key + " must lie in [1, 10^7]"};
    };
    if (key == "from") {
      const auto colon = value.find(':');
      const std::string kind = value.substr(0, colon),
                        rest = colon == std::string::npos ? "" : value.substr(colon + 1);
      if (kind == "surface" && rest.empty()) {
        r.seeds = session::SeedKind::Surface;
      } else if (kind == "slice" && !rest.empty()) {
        r.seeds = session::SeedKind::Slice;
        const auto c2 = rest.find(':');
        try {
          r.sliceAxis = static_cast<int>(surfaces::parseSliceAxis(rest.substr(0, c2)));
        } catch (const UsageError& e) {
          throw LineError{e.what()};
        }
        r.sliceIndex = c2 == std::string::npos ? -1 : integer(rest.substr(c2 + 1), "track slice index");
        if (c2 != std::string::npos && (r.sliceIndex < 0 || r.sliceIndex > 1'000'000))
          throw LineError{"track: slice index must lie in [0, 10^6]"};
      } else if (kind == "sphere" && !rest.empty()) {
        r.seeds = session::SeedKind::Sphere;
        double v[4];
        std::size_t at = 0;
        for (int k = 0; k < 4; ++k) {
          const auto comma = rest.find(',', at);
          if ((k < 3) == (comma == std::string::npos)) throw LineError{"track: from=sphere:X,Y,Z,R"};
          v[k] =
              number(rest.substr(at, comma == std::string::npos ? std::string::npos : comma - at), "sphere");
          at = comma + 1;
        }
        if (!(v[3] > 0 && v[3] <= 1000)) throw LineError{"track: the sphere radius must lie in (0, 1000] mm"};
        r.centre = glm::dvec3(v[0], v[1], v[2]);
        r.radiusMm = v[3];
      } else if (kind == "fa" && !rest.empty()) {
        r.seeds = session::SeedKind::FaMask;
        r.faMask = number(rest, "track FA mask");
        if (!(r.faMask > 0 && r.faMask < 1)) throw LineError{"track: from=fa:T needs 0 < T < 1"};
      } else {
        throw LineError{"track: from=surface | slice:AXIS[:I] | sphere:X,Y,Z,R | fa:T, got '" + value + "'"};
      }
    } else if (key == "select") {
      setCount(session::SeedCount::Select);
    } else if (key == "seeds") {
      setCount(session::SeedCount::Seeds);
    } else if (key == "per-voxel") {
      setCount(session::SeedCount::PerVoxel);
    } else if (const surfaces::TrackingParameter* p = surfaces::findTrackingParameter(key)) {
      try {
        p->set(r.options, p->parse(value));
      } catch (const UsageError& e) {
        throw LineError{std::string("track: ") + e.what()};
      }
    } else if (key == "seed") {
      const int seed = integer(value, "track seed");
      if (seed < 0) throw LineError{"track: seed must not be negative"};
      r.rngSeed = static_cast<std::uint64_t>(seed);
    } else {
      std::string known = "from, select, seeds, per-voxel, ";
      for (const auto& p : surfaces::trackingParameters())
        known += std::string(p.name) + ", ";
      throw LineError{"track: unknown option '" + key + "' (" + known + "seed, rk4, euler)"};
    }
  }
  if (r.count == session::SeedCount::PerVoxel && r.seeds != session::SeedKind::FaMask)
    throw LineError{"track: per-voxel needs from=fa:T"};
  try {
    session::validate(r);
  } catch (const UsageError& e) {
    throw LineError{std::string("track: ") + e.what()};
  }
  return r;
}

// Everything after the command word, for paths that may hold spaces.
std::string restOf(const std::string& line, const std::string& command) {
  return trim(line.substr(line.find(command) + command.size()));
}

// An output line's argument: "[--force] PATH".
std::pair<std::string, bool> outputArg(const std::string& arg, const char* usage) {
  const std::string flag = "--force";
  if (arg.compare(0, flag.size(), flag) != 0 ||
      (arg.size() > flag.size() && !std::isspace(static_cast<unsigned char>(arg[flag.size()]))))
    return {arg, false};
  std::string p = trim(arg.substr(flag.size()));
  if (p.empty()) throw LineError{std::string("usage: ") + usage};
  return {p, true};
}

} // namespace

// A script line split into words; path() is everything after the command word (paths may hold spaces).
struct ScriptLine {
  std::vector<std::string> words;
  std::string text;
  std::string path(const char* usage) const {
    std::string p = restOf(text, words[0]);
    if (p.empty()) throw LineError{std::string("usage: ") + usage};
    return p;
  }
};

namespace {

// load [layout=L] PATH: a tensor layout (fsl, mrtrix, symmatrix, dtitk) instead of the detected one.
void parseLoad(const ScriptLine& line, ScriptStep& step) {
  std::string path = line.path("load [layout=L] PATH"), layout = "auto";
  if (path.starts_with("layout=")) {
    const std::size_t end = path.find_first_of(" \t");
    if (end == std::string::npos) throw LineError{"usage: load [layout=L] PATH"};
    layout = path.substr(7, end - 7);
    try {
      io::parseLayout(layout);
    } catch (const UsageError& e) {
      throw LineError{std::string("load: ") + e.what()};
    }
    path = trim(path.substr(end));
  }
  step.command = session::Action(session::LoadFile{path, layout});
}

void parseSessionHeader(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "session 1");
  if (w[1] != "1") throw LineError{"session " + w[1] + ": this dtfabric reads session version 1"};
  step.command = ScriptWait{0};
}

// fibres [layout=L] [tensor=FILE] PATH: the options come first, the path is the rest of the line.
void parseFibres(const ScriptLine& line, ScriptStep& step) {
  static const char* const kUsage = "fibres [layout=L] [tensor=FILE] PATH";
  session::LoadFile load;
  load.layout = "fibres-auto";
  std::string rest = restOf(line.text, line.words[0]);
  while (rest.starts_with("layout=") || rest.starts_with("tensor=")) {
    const std::size_t end = rest.find_first_of(" \t");
    if (end == std::string::npos) throw LineError{std::string("usage: ") + kUsage};
    const std::string option = rest.substr(0, end);
    rest = restOf(rest, option);
    if (option.starts_with("layout=")) {
      load.layout = option.substr(7);
      if (load.layout != "auto" && !io::isFibreLayoutName(load.layout))
        throw LineError{"fibres: layout must be auto, mrtrix-peaks, dipy-peaks or bedpostx, got '" +
                        load.layout + "'"};
      if (load.layout == "auto") load.layout = "fibres-auto";
    } else {
      load.tensor = option.substr(7);
      if (load.tensor.empty()) throw LineError{std::string("usage: ") + kUsage};
    }
  }
  if (rest.empty()) throw LineError{std::string("usage: ") + kUsage};
  load.path = rest;
  step.command = session::Action(load);
}

void parseSurface(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "surface SPEC");
  try {
    session::parseSurfaceSpec(w[1]);
  } catch (const UsageError& e) {
    throw LineError{e.what()};
  }
  step.command = session::Action(session::SetSurfaceSpec{w[1]});
}

void parseFa(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "fa T");
  const double t = number(w[1], "fa threshold");
  if (t <= 0 || t >= 1) throw LineError{"fa threshold must lie in (0, 1), got " + w[1]};
  step.command = session::Action(session::SetFaThreshold{t});
}

void parseSlice(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 2, "slice axial|coronal|sagittal INDEX");
  int axis = 0;
  try {
    axis = static_cast<int>(surfaces::parseSliceAxis(w[1]));
  } catch (const UsageError& e) {
    throw LineError{e.what()};
  }
  const int index = integer(w[2], "slice index");
  if (index < 0) throw LineError{"slice index must not be negative"};
  step.command = session::Action(session::SetSlice{axis, index});
}

void parseKey(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "key Up|Down|PgUp|PgDn|A|C|S|R|F1");
  auto key = session::parseKey(w[1]);
  if (!key) throw LineError{"unknown key '" + w[1] + "' (Up, Down, PgUp, PgDn, A, C, S, R, F1)"};
  step.command = *key;
}

void parseRotate(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const std::string& c = line.words[0];
  expectArgs(w, 2, c == "rotate" ? "rotate DX DY" : "pan DX DY");
  const double dx = number(w[1], c + " DX"), dy = number(w[2], c + " DY");
  if (std::abs(dx) > 1e5 || std::abs(dy) > 1e5) throw LineError{c + ": drag too large"};
  step.command =
      c == "rotate" ? session::Action(session::Rotate{dx, dy}) : session::Action(session::Pan{dx, dy});
}

void parseZoom(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "zoom F");
  const double f = number(w[1], "zoom factor");
  if (f <= 0.01 || f > 100) throw LineError{"zoom factor must lie in (0.01, 100], got " + w[1]};
  step.command = session::Action(session::Zoom{f});
}

void parseView(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "view NAME");
  try {
    step.command = session::Action(session::SetView{render::parseView(w[1])});
  } catch (const UsageError& e) {
    throw LineError{e.what()};
  }
}

void parseSplit(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "split on|off|colour|phong|tracts");
  if (w[1] == "colour" || w[1] == "color")
    step.command = session::Action(session::SetSplit{true, session::SecondPane::OtherColourMode});
  else if (w[1] == "phong")
    step.command = session::Action(session::SetSplit{true, session::SecondPane::Phong});
  else if (w[1] == "tracts")
    step.command = session::Action(session::SetSplit{true, session::SecondPane::Tracts});
  else if (w[1] == "on" || w[1] == "off" || w[1] == "1" || w[1] == "0" || w[1] == "true" || w[1] == "false")
    step.command = session::Action(session::SetSplit{onOff(w[1], "split")});
  else
    throw LineError{"split takes on or off (or colour, phong, tracts), got '" + w[1] + "'"};
}

void parseLinked(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "linked on|off");
  step.command = session::Action(session::SetLinkedCameras{onOff(w[1], "linked")});
}

void parseNeurological(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "neurological on|off");
  step.command = session::Action(session::SetNeurological{onOff(w[1], "neurological")});
}

void parseSet(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 2, "set PARAM VALUE");
  step.command = parseParam(w[1], w[2]);
}

void parseWait(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "wait FRAMES");
  const int n = integer(w[1], "wait frames");
  if (n < 0 || n > 100000) throw LineError{"wait frames must lie in [0, 100000], got " + w[1]};
  step.command = ScriptWait{n};
}

void parseScreenshot(const ScriptLine& line, ScriptStep& step) {
  const std::string& c = line.words[0];
  const char* usage = c == "screenshot" ? "screenshot [--force] PATH" : "screenshot-scene [--force] PATH";
  const auto [p, force] = outputArg(line.path(usage), usage);
  if (p.size() < 4 || p.compare(p.size() - 4, 4, ".png") != 0)
    throw LineError{c + ": the path must end in .png"};
  step.command = session::Action(session::Screenshot{p, c == "screenshot-scene", force});
}

void parseCameraSave(const ScriptLine& line, ScriptStep& step) {
  const auto [p, force] = outputArg(line.path("camera-save [--force] PATH"), "camera-save [--force] PATH");
  step.command = session::Action(session::SaveCamera{p, force});
}

void parseCameraLoad(const ScriptLine& line, ScriptStep& step) {
  step.command = session::Action(session::LoadCamera{line.path("camera-load PATH")});
}

void parseProbe(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 2, "probe X Y");
  const double x = number(w[1], "probe X"), y = number(w[2], "probe Y");
  if (x < 0 || y < 0 || x > 1e5 || y > 1e5)
    throw LineError{"probe: pixel coordinates must be non-negative"};
  step.command = ScriptProbe{x, y};
}

void parseClick(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 2, "click X Y");
  const double x = number(w[1], "click X"), y = number(w[2], "click Y");
  if (x < 0 || y < 0 || x > 1e5 || y > 1e5) throw LineError{"click: pixel coordinates must be non-negative"};
  step.command = ScriptClick{x, y};
}

void parseLayout(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "layout single|ortho");
  if (w[1] != "single" && w[1] != "ortho") throw LineError{"layout takes single or ortho, got '" + w[1] + "'"};
  step.command = session::Action(session::SetOrtho{w[1] == "ortho"});
}

void parseCrosshair(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 3, "crosshair X Y Z");
  const glm::dvec3 p(number(w[1], "crosshair X"), number(w[2], "crosshair Y"), number(w[3], "crosshair Z"));
  if (std::abs(p.x) > 1e5 || std::abs(p.y) > 1e5 || std::abs(p.z) > 1e5)
    throw LineError{"crosshair: world coordinates beyond 10^5 mm"};
  step.command = session::Action(session::SetCrosshair{p});
}

void parseMovie(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const char* usage = "movie turntable FRAMES [--force] PATH | movie sweep AXIS FRAMES [--force] PATH | movie "
                      "fa-sweep LO:HI FRAMES [--force] PATH (PATH .mp4, .gif or DIR/)";
  session::RecordMovie m;
  const bool sweep = w.size() >= 2 && w[1] == "sweep", faSweep = w.size() >= 2 && w[1] == "fa-sweep";
  const std::size_t at = sweep || faSweep ? 3 : 2; // the FRAMES word
  if (w.size() < at + 2 || (!sweep && !faSweep && w[1] != "turntable")) throw LineError{std::string("usage: ") + usage};
  if (sweep) {
    if (w[2] != "axial" && w[2] != "coronal" && w[2] != "sagittal")
      throw LineError{"movie sweep AXIS: axial, coronal or sagittal, got '" + w[2] + "'"};
    m.kind = session::RecordMovie::Kind::Sweep;
    m.axis = w[2];
  } else if (faSweep) {
    const auto colon = w[2].find(':');
    if (colon == std::string::npos) throw LineError{std::string("usage: ") + usage};
    m.kind = session::RecordMovie::Kind::FaSweep;
    m.faLo = number(w[2].substr(0, colon), "movie fa-sweep LO");
    m.faHi = number(w[2].substr(colon + 1), "movie fa-sweep HI");
    if (!(m.faLo > 0 && m.faHi < 1 && m.faLo != m.faHi))
      throw LineError{"movie fa-sweep LO:HI: two different thresholds in (0, 1), got " + w[2]};
  }
  m.frames = integer(w[at], "movie frames");
  if (m.frames < 1 || m.frames > 10000) throw LineError{"movie frames must lie in [1, 10000], got " + w[at]};
  std::string rest = restOf(line.text, w[0]);
  for (std::size_t i = 1; i <= at; ++i) rest = restOf(rest, w[i]);
  const auto [p, force] = outputArg(rest, usage);
  try {
    io::movieFormatOf(p);
  } catch (const UsageError& e) {
    throw LineError{e.what()};
  }
  m.path = p;
  m.force = force;
  step.command = session::Action(m);
}

void parseBackground(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const char* usage = "background FILE|fa|md|none|default [LO,HI]";
  if (w.size() < 2 || w.size() > 3) throw LineError{std::string("usage: ") + usage};
  step.command = session::Action(session::SetBackground{w[1] == "default" ? "" : w[1], w.size() == 3 ? w[2] : ""});
}

// `fabric-along on|off [MM]`.
void parseFabricAlong(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const char* usage = "fabric-along on|off [MM]";
  if (w.size() < 2 || w.size() > 3) throw LineError{std::string("usage: ") + usage};
  session::SetFabricAlong a;
  a.on = onOff(w[1], "fabric-along");
  if (w.size() == 3) {
    const double mm = number(w[2], "fabric-along MM");
    if (!(mm > 0 && mm <= 1000)) throw LineError{"fabric-along MM must lie in (0, 1000], got " + w[2]};
    a.mm = mm;
  }
  step.command = session::Action(a);
}

// `profile on|off [fa|md|ad|rd]`.
void parseProfile(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const char* usage = "profile on|off [fa|md|ad|rd]";
  if (w.size() < 2 || w.size() > 3) throw LineError{std::string("usage: ") + usage};
  session::SetProfile a;
  a.on = onOff(w[1], "profile");
  if (w.size() == 3) {
    if (w[2] != "fa" && w[2] != "md" && w[2] != "ad" && w[2] != "rd" && w[2].find('=') == std::string::npos)
      throw LineError{"profile takes fa, md, ad, rd or NAME=IMAGE, not '" + w[2] + "'"};
    a.scalar = w[2];
  }
  step.command = session::Action(a);
}

// `profile-hover K|none [pin]`.
void parseProfileHover(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  const char* usage = "profile-hover K|none [pin]";
  if (w.size() < 2 || w.size() > 3 || (w.size() == 3 && w[2] != "pin"))
    throw LineError{std::string("usage: ") + usage};
  session::HoverProfileNode a;
  if (w[1] != "none") {
    const double k = number(w[1], "profile-hover K");
    if (!(k >= 0 && k == std::floor(k) && k < 100000))
      throw LineError{"profile-hover K must be a node index, got " + w[1]};
    a.node = static_cast<int>(k);
  }
  a.pin = w.size() == 3;
  step.command = session::Action(a);
}

void parseFurniture(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 2, "furniture legend|scale-bar|colour-bar|all on|off");
  const bool on = onOff(w[2], "furniture");
  session::SetFurniture f;
  if (w[1] == "legend" || w[1] == "all") f.legend = on;
  if (w[1] == "scale-bar" || w[1] == "all") f.scaleBar = on;
  if (w[1] == "colour-bar" || w[1] == "color-bar" || w[1] == "all") f.colourBar = on;
  if (!f.legend && !f.scaleBar && !f.colourBar)
    throw LineError{"furniture takes legend, scale-bar, colour-bar or all, got '" + w[1] + "'"};
  step.command = session::Action(f);
}

void parseResize(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "resize WxH");
  const auto x = w[1].find('x');
  if (x == std::string::npos) throw LineError{"usage: resize WxH"};
  const int width = integer(w[1].substr(0, x), "resize width");
  const int height = integer(w[1].substr(x + 1), "resize height");
  if (width < 320 || height < 240 || width > 8192 || height > 8192)
    throw LineError{"resize: the size must lie between 320x240 and 8192x8192"};
  step.command = ScriptResize{width, height};
}

void parseTracts(const ScriptLine& line, ScriptStep& step) {
  step.command = session::Action(session::LoadTracts{line.path("tracts PATH")});
}

void parseTractsVisible(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "tracts-visible on|off");
  step.command = session::Action(session::SetTractsVisible{onOff(w[1], "tracts-visible")});
}

void parseTractsNear(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "tracts-near MM");
  const double mm = number(w[1], "tracts-near");
  if (mm < 0 || mm > 1000) throw LineError{"tracts-near must lie in [0, 1000] mm, got " + w[1]};
  step.command = session::Action(session::SetTractsNear{mm});
}

void parseTractsClip(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  if (w.size() != 2 && w.size() != 3) throw LineError{"usage: tracts-clip MM [DEPTH_MM]"};
  const double mm = number(w[1], "tracts-clip");
  if (mm < 0 || mm > 1000) throw LineError{"tracts-clip must lie in [0, 1000] mm, got " + w[1]};
  const double offset = w.size() == 3 ? number(w[2], "tracts-clip depth") : 0.0;
  if (std::abs(offset) > 1000)
    throw LineError{"tracts-clip depth must lie in [-1000, 1000] mm, got " + w[2]};
  step.command = session::Action(session::SetTractsClip{mm, offset});
}

void parseTractsColour(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  if (w.size() != 2 && w.size() != 4) throw LineError{"usage: tracts-color NAME|dec [LO HI]"};
  session::SetTractColour c;
  if (w[1] != "dec") c.value = w[1];
  if (w.size() == 4) {
    if (c.value.empty()) throw LineError{"tracts-color dec takes no range"};
    const double lo = number(w[2], "tracts-color LO"), hi = number(w[3], "tracts-color HI");
    if (!(lo < hi)) throw LineError{"tracts-color needs LO < HI, got " + w[2] + " " + w[3]};
    c.range = std::make_pair(lo, hi);
  }
  step.command = session::Action(std::move(c));
}

void parseTractsGroups(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "tracts-groups G[,G...]|all|none");
  session::SetTractGroups g;
  g.all = w[1] == "all";
  if (!g.all && w[1] != "none") {
    std::size_t start = 0;
    while (start <= w[1].size()) {
      const std::size_t comma = std::min(w[1].find(',', start), w[1].size());
      if (comma == start) throw LineError{"tracts-groups: empty group name in '" + w[1] + "'"};
      g.shown.push_back(w[1].substr(start, comma - start));
      start = comma + 1;
    }
  }
  step.command = session::Action(std::move(g));
}

void parseTractWidth(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "tract-width PX");
  const double px = number(w[1], "tract-width");
  if (px <= 0 || px > 32) throw LineError{"tract-width must lie in (0, 32] pixels, got " + w[1]};
  step.command = session::Action(session::SetTractWidth{px});
}

void parseTrackLine(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  step.command = session::Action(session::TrackTracts{parseTrack(w)});
}

void parseTrackCancel(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 0, "track-cancel");
  step.command = session::Action(session::CancelTracking{});
}

void parseTractsSave(const ScriptLine& line, ScriptStep& step) {
  constexpr const char* usage = "tracts-save [--force] [--selected [--as-group NAME]] PATH";
  session::SaveTracts save;
  std::string rest = line.path(usage);
  while (rest.starts_with("--")) { // options before the path, which may hold spaces
    const std::size_t end = rest.find_first_of(" \t");
    if (end == std::string::npos) throw LineError{std::string("usage: ") + usage};
    const std::string option = rest.substr(0, end);
    rest = trim(rest.substr(end));
    if (option == "--force") {
      save.force = true;
    } else if (option == "--selected") {
      save.selected = true;
    } else if (option == "--as-group") {
      const std::size_t name = rest.find_first_of(" \t");
      if (name == std::string::npos) throw LineError{std::string("usage: ") + usage};
      save.asGroup = rest.substr(0, name);
      rest = trim(rest.substr(name));
    } else {
      throw LineError{"tracts-save: unknown option '" + option + "' (--force, --selected, --as-group NAME)"};
    }
  }
  if (rest.empty()) throw LineError{std::string("usage: ") + usage};
  if (!save.asGroup.empty() && !save.selected) throw LineError{"tracts-save: --as-group needs --selected"};
  save.path = rest;
  step.command = session::Action(save);
}

// roi add include|exclude|include-ordered SPEC | ends-only on|off | others hide|dim | clear | save [--force]
// FILE | load FILE
void parseRoi(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  constexpr const char* usage =
      "roi add include|exclude|include-ordered SPEC | ends-only on|off | others hide|dim | clear | save "
      "[--force] FILE.json | load FILE.json";
  if (w.size() < 2) throw LineError{std::string("usage: ") + usage};
  const std::string& what = w[1];
  if (what == "add") {
    if (w.size() < 4) throw LineError{"usage: roi add include|exclude|include-ordered SPEC"};
    session::RoiAdd add;
    if (w[2] == "include")
      add.kind = surfaces::RegionKind::Include;
    else if (w[2] == "exclude")
      add.kind = surfaces::RegionKind::Exclude;
    else if (w[2] == "include-ordered")
      add.kind = surfaces::RegionKind::IncludeOrdered;
    else
      throw LineError{"roi add: the kind is include, exclude or include-ordered, got '" + w[2] + "'"};
    add.spec = restOf(restOf(restOf(line.text, w[0]), w[1]), w[2]);
    step.command = session::Action(add);
  } else if (what == "ends-only") {
    expectArgs(w, 2, "roi ends-only on|off");
    step.command = session::Action(session::RoiEndsOnly{onOff(w[2], "roi ends-only")});
  } else if (what == "others") {
    expectArgs(w, 2, "roi others hide|dim");
    if (w[2] != "hide" && w[2] != "dim") throw LineError{"roi others takes hide or dim, got '" + w[2] + "'"};
    step.command = session::Action(session::RoiHideOthers{w[2] == "hide"});
  } else if (what == "clear") {
    expectArgs(w, 1, "roi clear");
    step.command = session::Action(session::RoiClear{});
  } else if (what == "save") {
    const std::string rest = restOf(restOf(line.text, w[0]), w[1]);
    if (rest.empty()) throw LineError{"usage: roi save [--force] FILE.json"};
    const auto [p, force] = outputArg(rest, "roi save [--force] FILE.json");
    step.command = session::Action(session::SaveRegions{p, force});
  } else if (what == "load") {
    const std::string rest = restOf(restOf(line.text, w[0]), w[1]);
    if (rest.empty()) throw LineError{"usage: roi load FILE.json"};
    step.command = session::Action(session::LoadRegions{rest});
  } else {
    throw LineError{"roi: unknown '" + what + "' (add, ends-only, others, clear, save, load)"};
  }
}

void parseAgreement(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  if (w.size() > 3) throw LineError{"usage: agreement [NEAR_MM [BINS]]"};
  session::ComputeAgreement a;
  if (w.size() > 1) a.nearMm = number(w[1], "agreement distance");
  if (w.size() > 2) a.bins = integer(w[2], "agreement bins");
  if (a.nearMm < 0 || a.nearMm > 1000) throw LineError{"agreement distance must lie in [0, 1000] mm"};
  if (a.bins < 1 || a.bins > 90) throw LineError{"agreement bins must lie in 1..90"};
  step.command = session::Action(a);
}

// "X,Y,Z" of a camera line's key.
glm::dvec3 triple(const std::string& text, const std::string& what) {
  glm::dvec3 v{0.0};
  std::size_t at = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = text.find(',', at);
    if ((k < 2) == (comma == std::string::npos))
      throw LineError{"camera " + what + "=X,Y,Z, got '" + text + "'"};
    v[k] = number(text.substr(at, comma == std::string::npos ? std::string::npos : comma - at),
                  "camera " + what);
    at = comma + 1;
  }
  if (std::abs(v.x) > 1e7 || std::abs(v.y) > 1e7 || std::abs(v.z) > 1e7)
    throw LineError{"camera " + what + ": beyond 10^7 mm"};
  return v;
}

// camera [pane=N] eye=X,Y,Z target=X,Y,Z up=X,Y,Z ortho=HALF_HEIGHT|fov=DEG near=N far=F
void parseCamera(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  session::SetCamera c;
  bool eye = false, target = false, up = false, projection = false;
  for (std::size_t i = 1; i < w.size(); ++i) {
    const auto eq = w[i].find('=');
    if (eq == std::string::npos || eq + 1 == w[i].size())
      throw LineError{"camera: expected KEY=VALUE, got '" + w[i] + "'"};
    const std::string key = w[i].substr(0, eq), value = w[i].substr(eq + 1);
    if (key == "pane") {
      c.pane = integer(value, "camera pane");
      if (c.pane < 0 || c.pane > 1) throw LineError{"camera pane must be 0 or 1"};
    } else if (key == "eye") {
      c.camera.eye = triple(value, key), eye = true;
    } else if (key == "target") {
      c.camera.target = triple(value, key), target = true;
    } else if (key == "up") {
      c.camera.up = triple(value, key), up = true;
    } else if (key == "ortho") {
      c.camera.orthographic = true;
      c.camera.orthoHalfHeight = number(value, "camera ortho");
      if (!(c.camera.orthoHalfHeight > 0 && c.camera.orthoHalfHeight < 1e7))
        throw LineError{"camera ortho: the half height must lie in (0, 10^7) mm"};
      projection = true;
    } else if (key == "fov") {
      c.camera.orthographic = false;
      c.camera.fovYDeg = number(value, "camera fov");
      if (!(c.camera.fovYDeg > 0 && c.camera.fovYDeg < 180))
        throw LineError{"camera fov must lie in (0, 180) degrees"};
      projection = true;
    } else if (key == "near") {
      c.camera.nearPlane = number(value, "camera near");
    } else if (key == "far") {
      c.camera.farPlane = number(value, "camera far");
    } else {
      throw LineError{"camera: unknown key '" + key + "' (pane, eye, target, up, ortho, fov, near, far)"};
    }
  }
  if (!eye || !target || !up || !projection)
    throw LineError{"usage: camera [pane=N] eye=X,Y,Z target=X,Y,Z up=X,Y,Z ortho=H|fov=DEG [near=N far=F]"};
  if (glm::length(c.camera.target - c.camera.eye) <= 0 || glm::length(c.camera.up) <= 0 ||
      glm::length(glm::cross(c.camera.target - c.camera.eye, c.camera.up)) <= 0)
    throw LineError{"camera: the eye, target and up make no view (eye on the target, or up along the view)"};
  if (!(c.camera.nearPlane > 0 && c.camera.farPlane > c.camera.nearPlane))
    throw LineError{"camera: needs 0 < near < far"};
  step.command = session::Action(c);
}

void parseSessionSave(const ScriptLine& line, ScriptStep& step) {
  const auto [p, force] = outputArg(line.path("session-save [--force] PATH"), "session-save [--force] PATH");
  step.command = session::Action(session::SaveSession{p, force});
}

void parseUiScale(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "ui-scale F|auto");
  const double f = w[1] == "auto" ? 0.0 : number(w[1], "ui-scale");
  if (w[1] != "auto" && !(f >= 0.5 && f <= 4)) throw LineError{"ui-scale must lie in [0.5, 4], got " + w[1]};
  step.command = session::Action(session::SetUiScale{f});
}

void parseHelp(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 1, "help on|off");
  step.command = session::Action(session::ShowHelp{onOff(w[1], "help")});
}

void parseBrowse(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  if (w.size() < 2) throw LineError{"usage: browse TARGET [FOLDER]"};
  const auto target = session::parseFileTarget(w[1]);
  if (!target)
    throw LineError{"browse: unknown target '" + w[1] +
                    "' (data, tensor, background, tracts, mesh, regions, screenshot, camera, movie, "
                    "tracts-save, session-save, regions-save, selected-save)"};
  step.command =
      session::Action(session::Browse{*target, w.size() > 2 ? restOf(restOf(line.text, w[0]), w[1]) : ""});
}

void parseBrowserPick(const ScriptLine& line, ScriptStep& step) {
  step.command = ScriptBrowserPick{line.path("browser-pick NAME")};
}

// The paths of a drop line: separated by spaces, a path holding spaces in single or double quotes.
void parseDrop(const ScriptLine& line, ScriptStep& step) {
  const std::string rest = restOf(line.text, line.words[0]);
  ScriptDrop drop;
  for (std::size_t i = 0; i < rest.size();) {
    if (std::isspace(static_cast<unsigned char>(rest[i]))) {
      ++i;
      continue;
    }
    std::size_t end;
    if (rest[i] == '\'' || rest[i] == '"') {
      end = rest.find(rest[i], i + 1);
      if (end == std::string::npos) throw LineError{"drop: unmatched quote"};
      drop.paths.push_back(rest.substr(i + 1, end - i - 1));
      ++end;
    } else {
      end = i;
      while (end < rest.size() && !std::isspace(static_cast<unsigned char>(rest[end])))
        ++end;
      drop.paths.push_back(rest.substr(i, end - i));
    }
    i = end;
  }
  if (drop.paths.empty()) throw LineError{"usage: drop PATH [PATH ...]"};
  step.command = std::move(drop);
}

void parseQuit(const ScriptLine& line, ScriptStep& step) {
  const std::vector<std::string>& w = line.words;
  expectArgs(w, 0, "quit");
  step.command = session::Action(session::Quit{});
}

// The script's commands, in the order help lists them.
const std::vector<ScriptCommand> kCommands = {
    {"session", "1",
     "first line of a saved session (session-save): every file the script names is checked before the window "
     "opens, and a missing one fails the run (exit code 2) with nothing shown",
     parseSessionHeader},
    {"load", "[layout=L] PATH",
     "open a tensor volume (or a DWI with sibling .bval/.bvec, or a fibre set it detects); L: a tensor "
     "layout instead of the detected one",
     parseLoad},
    {"fibres", "[layout=L] [tensor=FILE] PATH",
     "open a fibre set (peaks, bedpostx, ...) as `dtfabric render` does: L mrtrix-peaks|dipy-peaks|bedpostx "
     "(default: detected); tensor= pairs a tensor volume on the same grid (FA); the fibre threshold is `set "
     "fibre-threshold T`",
     parseFibres},
    {"surface", "SPEC",
     "any surface of `dtfabric render --surface` (fa=0.3, slice=axial:20, fibre-voxel=...)", parseSurface},
    {"fa", "T", "FA isosurface at T (0 < T < 1)", parseFa},
    {"slice", "AXIS INDEX", "axial, coronal or sagittal slice INDEX", parseSlice},
    {"key", "NAME",
     "a key: Up, Down, PgUp, PgDn (slice), A, C, S (slice axis), R (reset the view), F1 (help)", parseKey},
    {"rotate", "DX DY", "trackball drag by DX, DY window pixels (y down)", parseRotate},
    {"pan", "DX DY", "pan by DX, DY window pixels", parseRotate},
    {"zoom", "F", "magnify by F (2 = twice as large)", parseZoom},
    {"view", "NAME",
     "superior, inferior, anterior, posterior, left, right, or the display views axial, coronal, sagittal",
     parseView},
    {"neurological", "on|off", "neurological display convention (default off: radiological)",
     parseNeurological},
    {"resize", "WxH", "resize the window", parseResize},
    {"split", "on|off|colour|phong|tracts",
     "two panes; colour, phong and tracts also pick the right pane (the other colour mode, Phong shading, "
     "fabric + tracts beside the fabric alone)",
     parseSplit},
    {"linked", "on|off", "one camera for both panes", parseLinked},
    {"set", "NAME VALUE",
     "a fabric option, as `dtfabric render --NAME VALUE` (older names: k, r, colour, depth-colour, fade)",
     parseSet},
    {"tracts", "PATH", "load .tck/.trk/.vtk streamlines (world RAS mm) and draw them over the fabric",
     parseTracts},
    {"tracts-visible", "on|off", "show or hide the tracts", parseTractsVisible},
    {"tracts-near", "MM", "only tract segments within MM of the surface (0 = every tract; default 3)",
     parseTractsNear},
    {"tracts-clip", "MM [DEPTH]",
     "clip slab for dense tractograms: only points within MM of the plane facing the camera through the "
     "surface's centre, moved DEPTH mm away from the viewer (0 = off); on a planar surface, within MM of its "
     "plane",
     parseTractsClip},
    {"tracts-color", "NAME|dec [LO HI]",
     "colour the tracts by the per-point or per-streamline value NAME through the viewer's colour map over "
     "LO..HI (default: the value's min..max); dec: direction colours; node: the node index (0..99) along the "
     "bundle oriented and resampled as `dtfabric profile` does; profile: the Profile panel's value (e.g. FA) "
     "at "
     "each point's node",
     parseTractsColour},
    {"tracts-groups", "G[,G...]|all|none",
     "show only the streamlines of the named groups (e.g. an AFQ .trx's bundles); all: every streamline",
     parseTractsGroups},
    {"tract-width", "PX", "tube width in pixels (default 2)", parseTractWidth},
    {"track", "[KEY=VALUE ...]",
     "tracking on the worker, as `dtfabric track`: from=surface|slice:AXIS[:I]|sphere:X,Y,Z,R|fa:T, "
     "select=N|seeds=N|per-voxel=K, fa-stop=F angle=DEG step=MM min-length=MM max-length=MM seed=S rk4|euler",
     parseTrackLine},
    {"track-cancel", "", "cancel a running `track`", parseTrackCancel},
    {"tracts-save", "[--force] [--selected [--as-group NAME]] PATH",
     "write every point of the tracts to .tck/.trk/.trx/.vtk; --selected: only the streamlines the regions "
     "select (every value and group kept, as `dtfabric select`); --as-group NAME: every streamline, the "
     "selection added as group NAME of a .trx",
     parseTractsSave},
    {"roi", "add KIND SPEC | ends-only on|off | others hide|dim | clear | save [--force] FILE | load FILE",
     "the regions that select streamlines, as `dtfabric select`: add a region (KIND include, exclude or "
     "include-ordered; SPEC X,Y,Z,R, box:X0,Y0,Z0,X1,Y1,Z1, IMAGE or IMAGE:L[,L...]), test the end points "
     "only, "
     "hide or dim the streamlines left out, remove every region, save or load the region set (`select --roi` "
     "JSON); a later line waits for the selection",
     parseRoi},
    {"agreement", "[MM [BINS]]",
     "tract/fabric angles within MM (default 2) of the surface in BINS bins (default 9); prints `dtfabric "
     "compare`'s numbers",
     parseAgreement},
    {"screenshot", "[--force] PATH", "PNG of the whole window, panels included", parseScreenshot},
    {"screenshot-scene", "[--force] PATH",
     "PNG of the fabric panes only with their furniture (legend, scale bar, colour bar; no panels, no edge "
     "letters; in the ortho layout the whole layout with its crosshair and orientation letters)",
     parseScreenshot},
    {"layout", "single|ortho",
     "ortho: axial, coronal and sagittal slices through the crosshair beside the 3D pane; single: the 3D "
     "view alone (or split)",
     parseLayout},
    {"crosshair", "X Y Z",
     "move the ortho layout's crosshair to world RAS X, Y, Z mm (the slice panes follow); prints it with its "
     "slices to stderr",
     parseCrosshair},
    {"click", "X Y",
     "a click at scene pixel (X, Y) (y down): in an ortho slice pane it moves the crosshair there; prints it "
     "to stderr",
     parseClick},
    {"movie", "turntable|sweep AXIS|fa-sweep LO:HI FRAMES [--force] PATH",
     "record what the 3D pane shows (its surface, fabric and camera): a full turn about its vertical axis, a "
     "sweep of AXIS slices through the data, or the FA isosurface from LO to HI; FRAMES frames to PATH .mp4 "
     "or .gif (ffmpeg on PATH) or DIR/ (PNG frames), the advection state carried from frame to frame",
     parseMovie},
    {"background", "FILE|fa|md|none|default [LO,HI]",
     "the grey beneath the fabric: a scalar volume on any grid (resampled in world space), the data's FA or "
     "MD, "
     "none (FA within the data), default (a DWI's mean b=0 image); LO,HI: its grey ramp",
     parseBackground},
    {"fabric-along", "on|off [MM]",
     "draw the fabric only within MM (default 2) mm of the tracts on screen, the grey beneath elsewhere (FA "
     "when no background is chosen), as `dtfabric render --fabric-along`",
     parseFabricAlong},
    {"profile", "on|off [fa|md|ad|rd|NAME=IMAGE]",
     "the Profile panel: profile the tracts on screen along a scalar (default fa; NAME=IMAGE: any scalar "
     "image, as `dtfabric profile --scalar`) as `dtfabric profile` does",
     parseProfile},
    {"profile-hover", "K|none [pin]",
     "hover node K of the profile (the crosshair goes to its core position); pin: pin it (again: unpin)",
     parseProfileHover},
    {"furniture", "legend|scale-bar|colour-bar|all on|off",
     "the figure furniture over the panes (and in screenshot-scene): the DEC orientation legend, the scale "
     "bar, "
     "the tract value's colour bar",
     parseFurniture},
    {"camera-save", "[--force] PATH", "write the camera (eye, target, up, projection)", parseCameraSave},
    {"camera", "[pane=N] eye=X,Y,Z target=X,Y,Z up=X,Y,Z ortho=H|fov=DEG [near=N far=F]",
     "set the camera as it is (a saved session's): world RAS mm, the orthographic half height or the "
     "perspective field of view; pane 0 or 1 of an unlinked split (default: the active pane)",
     parseCamera},
    {"session-save", "[--force] PATH",
     "write a view script that brings the viewer back to what is on screen (`view --script PATH`)",
     parseSessionSave},
    {"drop", "PATH [PATH ...]",
     "files dropped on the window, each opened by its kind (a volume as data, a tractogram as tracts, a "
     "mesh as the surface); quotes around a path with spaces",
     parseDrop},
    {"browse", "TARGET [FOLDER]",
     "the file dialog for TARGET (data, tensor, background, tracts, mesh, screenshot, camera, movie, "
     "tracts-save, session-save): the desktop's, or the in-window browser where no portal runs",
     parseBrowse},
    {"browser-pick", "NAME",
     "in the in-window browser: enter folder NAME (.. the parent) or choose file NAME, as a double click",
     parseBrowserPick},
    {"ui-scale", "F|auto", "the panels', fonts' and furniture's scale (auto: the monitor's)", parseUiScale},
    {"help", "on|off", "the mouse and keyboard bindings over the scene (F1 or ?)", parseHelp},
    {"camera-load", "PATH", "read a camera file", parseCameraLoad},
    {"probe", "X Y", "print the voxel under scene pixel (X, Y) (y down) to stderr", parseProbe},
    {"wait", "FRAMES", "render FRAMES more frames", parseWait},
    {"quit", "", "close the viewer (exit code 2 when a step failed, 3 for a GL failure)", parseQuit},
};

ScriptStep parseLine(const std::string& text, int number_) {
  ScriptStep step;
  step.line = number_;
  const ScriptLine line{words(text), text};
  for (const ScriptCommand& command : kCommands)
    if (line.words[0] == command.name) {
      command.parse(line, step);
      return step;
    }
  std::string names;
  for (const ScriptCommand& command : kCommands)
    names += (names.empty() ? "" : ", ") + std::string(command.name);
  throw LineError{"unknown command '" + line.words[0] + "' (" + names + ")"};
}

} // namespace

const std::vector<ScriptCommand>& scriptCommands() { return kCommands; }

std::string scriptCommandsHelp() {
  std::string out;
  for (const ScriptCommand& c : kCommands) {
    std::string head = std::string("  ") + c.name + (*c.args ? " " : "") + c.args;
    head.resize(std::max<std::size_t>(head.size() + 2, 30), ' ');
    out += head + c.help + "\n";
  }
  return out;
}

ViewScript parseViewScript(const std::string& text, const std::string& file) {
  ViewScript script;
  script.file = file;
  std::istringstream in(text);
  std::string raw;
  int n = 0;
  while (std::getline(in, raw)) {
    ++n;
    if (raw.find('\0') != std::string::npos)
      throw UsageError(file + ":" + std::to_string(n) + ": NUL byte in script");
    const auto hash = raw.find('#');
    const std::string line = trim(hash == std::string::npos ? raw : raw.substr(0, hash));
    if (line.empty()) continue;
    try {
      script.steps.push_back(parseLine(line, n));
      if (words(line)[0] == "session") {
        if (script.steps.size() != 1) throw LineError{"session must be the script's first command"};
        script.session = true;
      }
    } catch (const LineError& e) {
      throw UsageError(file + ":" + std::to_string(n) + ": " + e.message);
    }
  }
  return script;
}

ViewScript loadViewScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the script");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (ss.str().size() > (16u << 20)) throw InputError(path + ": script larger than 16 MiB");
  return parseViewScript(ss.str(), path);
}

void checkScriptOutputs(const ViewScript& script, std::vector<std::string> inputs, bool force) {
  inputs.push_back(script.file);
  for (const ScriptStep& step : script.steps) {
    if (const auto* drop = std::get_if<ScriptDrop>(&step.command))
      inputs.insert(inputs.end(), drop->paths.begin(), drop->paths.end());
    const auto* a = std::get_if<session::Action>(&step.command);
    if (!a) continue;
    if (const auto* load = std::get_if<session::LoadFile>(a)) {
      inputs.push_back(load->path);
      inputs.push_back(io::gradientSibling(load->path, ".bval"));
      inputs.push_back(io::gradientSibling(load->path, ".bvec"));
    } else if (const auto* tracts = std::get_if<session::LoadTracts>(a)) {
      inputs.push_back(tracts->path);
    } else if (const auto* regions = std::get_if<session::LoadRegions>(a)) {
      inputs.push_back(regions->path);
    } else if (const auto* camera = std::get_if<session::LoadCamera>(a)) {
      inputs.push_back(camera->path);
    } else if (const auto* bg = std::get_if<session::SetBackground>(a)) {
      inputs.push_back(bg->what);
    } else if (const auto* surface = std::get_if<session::SetSurfaceSpec>(a)) {
      const session::SurfaceSpec spec = session::parseSurfaceSpec(surface->text);
      inputs.push_back(spec.file);
      for (const auto& part : spec.parts)
        inputs.push_back(part.file);
    }
  }
  for (const ScriptStep& step : script.steps) {
    const auto* a = std::get_if<session::Action>(&step.command);
    const auto* shot = a ? std::get_if<session::Screenshot>(a) : nullptr;
    const auto* camera = a ? std::get_if<session::SaveCamera>(a) : nullptr;
    const auto* tracts = a ? std::get_if<session::SaveTracts>(a) : nullptr;
    const auto* movie = a ? std::get_if<session::RecordMovie>(a) : nullptr;
    const auto* saved = a ? std::get_if<session::SaveSession>(a) : nullptr;
    const auto* regions = a ? std::get_if<session::SaveRegions>(a) : nullptr;
    if (!shot && !camera && !tracts && !movie && !saved && !regions) continue;
    const std::string& path = shot      ? shot->path
                              : camera  ? camera->path
                              : tracts  ? tracts->path
                              : movie   ? movie->path
                              : regions ? regions->path
                                        : saved->path;
    const bool lineForce = shot      ? shot->force
                           : camera  ? camera->force
                           : tracts  ? tracts->force
                           : movie   ? movie->force
                           : regions ? regions->force
                                     : saved->force;
    const std::string where = script.file + ":" + std::to_string(step.line) + ": ";
    try {
      io::refuseOverwritingInput(path, inputs);
      if (movie) io::refuseMovieOverInputs(path, inputs);
    } catch (const InputError& e) {
      throw InputError(where + e.what());
    }
    if (!force && !lineForce && io::outputExists(path))
      throw InputError(where + path +
                       " exists (use --force to overwrite it: `view --force`, or --force before "
                       "the path on this line)");
  }
}

void checkSessionInputs(const ViewScript& script) {
  if (!script.session) return;
  for (const ScriptStep& step : script.steps) {
    const auto* a = std::get_if<session::Action>(&step.command);
    if (!a) continue;
    std::vector<std::string> files;
    if (const auto* load = std::get_if<session::LoadFile>(a)) {
      files = {load->path, load->tensor};
    } else if (const auto* tracts = std::get_if<session::LoadTracts>(a)) {
      files = {tracts->path};
    } else if (const auto* regions = std::get_if<session::LoadRegions>(a)) {
      files = {regions->path};
    } else if (const auto* camera = std::get_if<session::LoadCamera>(a)) {
      files = {camera->path};
    } else if (const auto* bg = std::get_if<session::SetBackground>(a)) {
      if (bg->what != "fa" && bg->what != "md" && bg->what != "none") files = {bg->what};
    } else if (const auto* surface = std::get_if<session::SetSurfaceSpec>(a)) {
      const session::SurfaceSpec spec = session::parseSurfaceSpec(surface->text);
      files.push_back(spec.file);
      for (const auto& part : spec.parts)
        files.push_back(part.file);
    }
    for (const std::string& f : files) {
      std::error_code ec;
      if (!f.empty() && !std::filesystem::exists(f, ec) && io::dtifitSetOf(f).empty())
        throw InputError(script.file + ":" + std::to_string(step.line) + ": " + f +
                         ": no such file (the session names it; nothing was opened)");
    }
  }
}

void applyScriptParam(render::FabricParams& p, const ScriptSetParam& s) {
  if (const render::FabricOption* o = render::findFabricOption(s.name)) o->set(p, s.value);
}

} // namespace dtf::app
