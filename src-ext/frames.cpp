#include "frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "common/error.hpp"

namespace ricochet::dem {
namespace fs = std::filesystem;

namespace {

/// Whitespace-separated tokens of a file, with the section being read for error messages.
class Tokens {
 public:
  explicit Tokens(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path, 0, "file", "cannot open the VTK file");
  }
  std::string word(const std::string& section) {
    std::string w;
    if (!(in_ >> w)) fail(section, "the file ends early");
    return w;
  }
  double number(const std::string& section) {
    const std::string w = word(section);
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0') fail(section, "'" + w + "' is not a number");
    return v;
  }
  std::size_t count(const std::string& section) {
    const double v = number(section);
    if (!(v >= 0 && v == std::floor(v) && v < 1e10)) fail(section, "bad count");
    return static_cast<std::size_t>(v);
  }
  void expect(const std::string& section, const std::string& want) {
    const std::string w = word(section);
    if (w != want) fail(section, "expected '" + want + "', found '" + w + "'");
  }
  bool next(std::string& w) { return static_cast<bool>(in_ >> w); }
  [[noreturn]] void fail(const std::string& section, const std::string& why) const {
    throw InputError(path_, 0, section, why);
  }

 private:
  std::string path_;
  std::ifstream in_;
};

}  // namespace

Particles read_vtk_particles(const std::string& path) {
  {
    std::ifstream head(path);
    std::string line;
    std::getline(head, line);
    if (line.rfind("# vtk DataFile Version", 0) != 0)
      throw InputError(path, 1, "header", "not a legacy VTK file");
    std::getline(head, line);  // title
    std::getline(head, line);
    if (line.rfind("ASCII", 0) != 0) throw InputError(path, 3, "format", "only ASCII is read");
  }
  Tokens t(path);
  std::string w;
  while (t.next(w) && w != "DATASET") {
  }
  t.expect("DATASET", "POLYDATA");
  t.expect("POINTS", "POINTS");
  const std::size_t n = t.count("POINTS");
  t.word("POINTS");  // data type
  Particles p;
  p.x.resize(n);
  for (auto& x : p.x)
    for (double& c : x) c = t.number("POINTS");
  bool have_data = false;
  while (t.next(w)) {
    if (w == "VERTICES") {
      const std::size_t a = t.count("VERTICES"), b = t.count("VERTICES");
      std::string next = t.word("VERTICES");
      if (next == "OFFSETS") {  // VTK 5.1: offsets (a values) then connectivity (b values)
        t.word("OFFSETS");
        for (std::size_t i = 0; i < a; ++i) t.number("OFFSETS");
        t.expect("CONNECTIVITY", "CONNECTIVITY");
        t.word("CONNECTIVITY");
        for (std::size_t i = 0; i < b; ++i) t.number("CONNECTIVITY");
      } else {  // older form: b integers, the first already read
        for (std::size_t i = 1; i < b; ++i) t.number("VERTICES");
      }
    } else if (w == "POINT_DATA") {
      if (t.count("POINT_DATA") != n) t.fail("POINT_DATA", "count differs from POINTS");
      have_data = true;
    } else if (w == "FIELD") {
      t.word("FIELD");
      const std::size_t arrays = t.count("FIELD");
      for (std::size_t a = 0; a < arrays; ++a) {
        const std::string name = t.word("FIELD");
        const std::size_t comps = t.count(name), tuples = t.count(name);
        t.word(name);  // type
        if (tuples != n) t.fail(name, fmt::format("{} tuples for {} points", tuples, n));
        if (name == "v" && comps != 3) t.fail(name, "velocity needs 3 components");
        std::vector<double> values(comps * tuples);
        for (double& v : values) v = t.number(name);
        if (name == "v") {
          p.v.resize(n);
          for (std::size_t i = 0; i < n; ++i)
            p.v[i] = {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
        } else if (name == "radius" && comps == 1) {
          p.radius = values;
        } else if (name == "id" && comps == 1) {
          p.id.assign(values.begin(), values.end());
        }
      }
    }
  }
  if (!have_data || p.v.size() != n || p.radius.size() != n)
    t.fail("POINT_DATA", "needs the arrays v (3 components) and radius for every point");
  return p;
}

Particles read_dump_particles(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "file", "cannot open the dump file");
  std::string line;
  std::size_t line_no = 0, n = 0;
  bool have_n = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
      if (!std::getline(in, line))
        throw InputError(path, line_no + 1, "NUMBER OF ATOMS", "missing");
      ++line_no;
      n = static_cast<std::size_t>(std::stoul(line));
      have_n = true;
    } else if (line.rfind("ITEM: ATOMS", 0) == 0) {
      if (!have_n) throw InputError(path, line_no, "ATOMS", "no NUMBER OF ATOMS before");
      std::istringstream head(line.substr(11));
      std::map<std::string, std::size_t> col;
      std::string name;
      for (std::size_t c = 0; head >> name; ++c) col[name] = c;
      for (const char* need : {"id", "x", "y", "z", "vx", "vy", "vz", "radius"})
        if (!col.count(need)) throw InputError(path, line_no, need, "column missing");
      Particles p;
      std::vector<double> row(col.size());
      for (std::size_t i = 0; i < n; ++i) {
        if (!std::getline(in, line))
          throw InputError(path, line_no, "ATOMS",
                           fmt::format("{} atoms announced, {} found", n, i));
        ++line_no;
        std::istringstream r(line);
        for (double& v : row)
          if (!(r >> v)) throw InputError(path, line_no, "ATOMS", "too few or malformed values");
        p.id.push_back(static_cast<long>(row[col["id"]]));
        p.x.push_back({row[col["x"]], row[col["y"]], row[col["z"]]});
        p.v.push_back({row[col["vx"]], row[col["vy"]], row[col["vz"]]});
        p.radius.push_back(row[col["radius"]]);
      }
      return p;
    }
  }
  throw InputError(path, line_no, "ATOMS", "no ITEM: ATOMS section");
}

std::vector<long> frame_steps(const std::string& dir, const std::string& ext) {
  std::set<long> grains, block;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      if (!name.ends_with(ext) || name.find("_boundingBox_") != std::string::npos) continue;
      const auto us = name.find('_');
      if (us == std::string::npos) continue;
      const std::string kind = name.substr(0, us),
                        num = name.substr(us + 1, name.size() - us - 1 - ext.size());
      if (num.empty() || !std::all_of(num.begin(), num.end(), ::isdigit)) continue;
      if (kind == "grains") grains.insert(std::stol(num));
      if (kind == "block") block.insert(std::stol(num));
    }
  std::vector<long> both;
  std::set_intersection(grains.begin(), grains.end(), block.begin(), block.end(),
                        std::back_inserter(both));
  return both;
}

ImpactSnapshot snapshot_from_frames(const std::string& dir, const std::string& impact_id,
                                    double dt_s, int frames) {
  const auto steps = frame_steps(dir, ".txt");
  if (steps.empty()) throw InputError(dir, 0, "frames", "no grains_STEP.txt/block_STEP.txt pair");
  const auto file = [&](const char* kind, long step) {
    return (fs::path(dir) / fmt::format("{}_{}.txt", kind, step)).string();
  };
  // The bed's initial surface: the top of the first frame's grains (99th percentile of z + r,
  // so that a grain thrown up does not set it). The block's size and mid-plane from its spheres.
  const Particles first = read_dump_particles(file("grains", steps.front()));
  std::vector<double> tops;
  double r_grain_max = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    tops.push_back(first.x[i][2] + first.radius[i]);
    r_grain_max = std::max(r_grain_max, first.radius[i]);
  }
  std::sort(tops.begin(), tops.end());
  const double surface = tops[tops.size() * 99 / 100];
  std::vector<Particles> blocks;
  std::vector<double> lowest;
  for (long s : steps) {
    blocks.push_back(read_dump_particles(file("block", s)));
    double low = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < blocks.back().size(); ++i)
      low = std::min(low, blocks.back().x[i][2] - blocks.back().radius[i]);
    lowest.push_back(low);
  }
  std::vector<std::size_t> contact;
  for (std::size_t k = 0; k < steps.size(); ++k)
    if (lowest[k] < surface) contact.push_back(k);
  if (contact.empty())
    throw InputError(dir, 0, "frames", "no frame has the block below the bed's surface");
  const std::size_t deepest =
      *std::min_element(contact.begin(), contact.end(),
                        [&](std::size_t a, std::size_t b) { return lowest[a] < lowest[b]; });
  // Evenly spread over the contact, then the nearest one replaced by the deepest.
  std::set<std::size_t> chosen;
  const std::size_t want =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(frames, 1)), contact.size());
  for (std::size_t j = 0; j < want; ++j)
    chosen.insert(contact[want == 1 ? 0 : j * (contact.size() - 1) / (want - 1)]);
  if (!chosen.count(deepest)) {
    const auto nearest = std::min_element(chosen.begin(), chosen.end(), [&](auto a, auto b) {
      return std::abs(static_cast<long>(a) - static_cast<long>(deepest)) <
             std::abs(static_cast<long>(b) - static_cast<long>(deepest));
    });
    chosen.erase(nearest);
    chosen.insert(deepest);
  }
  const Particles& b0 = blocks[deepest];
  double y_mid = 0, xlo = 1e300, xhi = -1e300, zlo = 1e300;
  for (std::size_t i = 0; i < b0.size(); ++i) y_mid += b0.x[i][1] / static_cast<double>(b0.size());
  double block_r = 0;
  {
    double x0 = 1e300, x1 = -1e300;
    for (std::size_t i = 0; i < b0.size(); ++i) {
      x0 = std::min(x0, b0.x[i][0] - b0.radius[i]);
      x1 = std::max(x1, b0.x[i][0] + b0.radius[i]);
    }
    block_r = 0.5 * (x1 - x0);
  }
  for (std::size_t k : chosen)
    for (std::size_t i = 0; i < blocks[k].size(); ++i) {
      xlo = std::min(xlo, blocks[k].x[i][0]);
      xhi = std::max(xhi, blocks[k].x[i][0]);
      zlo = std::min(zlo, blocks[k].x[i][2]);
    }
  xlo -= 2 * block_r;
  xhi += 2 * block_r;
  zlo -= 2 * block_r;

  ImpactSnapshot snap;
  snap.impact_id = impact_id;
  snap.section_y_m = y_mid;
  snap.section_half_width_m = r_grain_max;
  for (std::size_t k : chosen) {
    SnapshotFrame f;
    f.step = steps[k];
    f.t_s = static_cast<double>(steps[k] - steps[contact.front()]) * dt_s;
    f.max_penetration = k == deepest;
    const Particles g = read_dump_particles(file("grains", steps[k]));
    for (std::size_t i = 0; i < g.size(); ++i) {
      const auto& x = g.x[i];
      if (std::abs(x[1] - y_mid) > r_grain_max || x[0] < xlo || x[0] > xhi || x[2] < zlo) continue;
      f.grain_x_m.push_back(x[0]);
      f.grain_z_m.push_back(x[2]);
      f.grain_speed_mps.push_back(std::hypot(g.v[i][0], g.v[i][1], g.v[i][2]));
      f.grain_radius_m.push_back(g.radius[i]);
    }
    for (std::size_t i = 0; i < blocks[k].size(); ++i) {
      f.block_x_m.push_back(blocks[k].x[i][0]);
      f.block_z_m.push_back(blocks[k].x[i][2]);
      f.block_radius_m.push_back(blocks[k].radius[i]);
    }
    snap.frames.push_back(std::move(f));
  }
  return snap;
}

}  // namespace ricochet::dem
