// SPDX-License-Identifier: GPL-3.0-or-later
// box_loads: the pressure force the solver's pressure integration gives an axis-aligned box from a
// storm file, record by record, next to OpenFOAM's forces function object on the same box
// (foam-bridge/tests/measure-surge-box, docs/foam-bridge.md "Where the voxels sit", "Wet and dry",
// "A unit on an impermeable bed").
//
// The box's faces are cut into square elements of side h; each element's centroid is sampled with
// StormSampler::sampleExtended, as solver/hydro/StormLoads does (gap fill included), and its
// pressure taken by one of three wet/dry rules:
//   threshold: p where alpha >= 0.5, else 0 (atmospheric): the solver's rule (hydro.storm.wet_alpha);
//   alpha:     alpha p (an alpha-weighted pressure);
//   plain:     p whatever alpha.
// The bottom face (z = z0) is integrated separately: a box resting on an impermeable floor has no
// bottom face in OpenFOAM (the floor is there), while the solver integrates every face of a unit.
//
// usage: box_loads STORM.nc x0 x1 y0 y1 z0 z1 h FORCE.dat [t0 t1]
// prints a CSV per record: time, OpenFOAM's pressure Fx Fz, per rule Fx and Fz without the bottom,
// the bottom face's Fz (threshold rule), and of the x and top faces the wet elements and those that
// took the gap fill.

#include "storm/StormFile.hpp"
#include "storm/StormSampler.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace armour;

namespace {

struct Element {
  double x, z, area;
  std::array<double, 3> normal; // outward
  bool bottom;
};

std::vector<Element> boxElements(const double b[6], double h) {
  std::vector<Element> out;
  const auto cut = [h](double a, double c) { return std::max(1, static_cast<int>(std::lround((c - a) / h))); };
  // faces: -x, +x (y-z planes), -y, +y (x-z planes), -z, +z (x-y planes)
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const double lo[3] = {b[0], b[2], b[4]}, hi[3] = {b[1], b[3], b[5]};
      const int nu = cut(lo[u], hi[u]), nv = cut(lo[v], hi[v]);
      const double du = (hi[u] - lo[u]) / nu, dv = (hi[v] - lo[v]) / nv;
      for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
          double c[3];
          c[axis] = side ? hi[axis] : lo[axis];
          c[u] = lo[u] + (i + 0.5) * du;
          c[v] = lo[v] + (j + 0.5) * dv;
          Element e{c[0], c[2], du * dv, {0, 0, 0}, axis == 2 && side == 0};
          e.normal[static_cast<std::size_t>(axis)] = side ? 1.0 : -1.0;
          out.push_back(e);
        }
      }
    }
  }
  return out;
}

/// time -> (pressure Fx, Fz) of forces/force.dat: "t ((Fx Fy Fz) (px py pz) (vx vy vz))".
std::map<double, std::array<double, 2>> readForces(const std::string& file) {
  std::map<double, std::array<double, 2>> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    for (char& c : line)
      if (c == '(' || c == ')') c = ' ';
    std::istringstream s(line);
    double t, v[9];
    if (!(s >> t)) continue;
    for (double& x : v) s >> x;
    out[std::round(t * 1e6) / 1e6] = {v[3], v[5]};
  }
  return out;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 10) {
    std::fprintf(stderr, "usage: box_loads STORM.nc x0 x1 y0 y1 z0 z1 h FORCE.dat [t0 t1]\n");
    return 2;
  }
  double box[6];
  for (int i = 0; i < 6; ++i) box[i] = std::stod(argv[2 + i]);
  const double h = std::stod(argv[8]);
  const auto forces = readForces(argv[9]);
  const double t0 = argc > 10 ? std::stod(argv[10]) : -1e300, t1 = argc > 11 ? std::stod(argv[11]) : 1e300;
  const storm::StormReader reader(argv[1]);
  storm::StormSampler sampler(reader);
  const std::vector<Element> elements = boxElements(box, h);
  std::printf("time,of_fx,of_fz,thr_fx,thr_fz,alpha_fx,alpha_fz,plain_fx,plain_fz,bottom_fz,wet,filled\n");
  for (double t : reader.times()) {
    if (t < t0 || t > t1) continue;
    sampler.setTime(t);
    double f[3][2] = {{0, 0}, {0, 0}, {0, 0}}, bottom = 0.0;
    long wet = 0, filled = 0;
    for (const Element& e : elements) {
      const storm::FlowSample s = sampler.sampleExtended(e.x, e.z);
      if (!s.valid) continue;
      const double p[3] = {s.alpha >= 0.5 ? s.p : 0.0, s.alpha * s.p, s.p};
      // The gap-fill share of the faces that carry Fx and Fz (the +-y faces cancel, the bottom is
      // reported apart), as the solver's log counts it: wet samples that took the gap fill.
      if (s.alpha >= 0.5 && e.normal[1] == 0.0 && !e.bottom) {
        ++wet;
        filled += s.filled ? 1 : 0;
      }
      if (e.bottom) {
        bottom -= p[0] * e.area * e.normal[2];
        continue;
      }
      for (int r = 0; r < 3; ++r) {
        f[r][0] -= p[r] * e.area * e.normal[0];
        f[r][1] -= p[r] * e.area * e.normal[2];
      }
    }
    const auto it = forces.find(std::round(t * 1e6) / 1e6);
    const double ofx = it == forces.end() ? NAN : it->second[0], ofz = it == forces.end() ? NAN : it->second[1];
    std::printf("%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%ld,%ld\n", t, ofx, ofz, f[0][0], f[0][1], f[1][0],
                f[1][1], f[2][0], f[2][1], bottom, wet, filled);
  }
  return 0;
}
