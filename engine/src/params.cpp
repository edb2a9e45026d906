// Derived material quantities and validation of the scene parameters.
#include "compaction/params.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "compaction/number_text.hpp"

namespace compaction {

double SceneParams::lame_lambda() const {
  const double E = youngs_modulus();
  return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}
double SceneParams::lame_mu() const { return youngs_modulus() / (2.0 * (1.0 + nu)); }
double SceneParams::bar_wave_speed() const { return std::sqrt(youngs_modulus() / rho); }
double SceneParams::p_wave_speed() const {
  return std::sqrt((lame_lambda() + 2.0 * lame_mu()) / rho);
}
double SceneParams::hole_side() const {
  return unit_cell() * (geometry == Geometry::pseudo1d_3d ? std::cbrt(1.0 - phi)
                                                          : std::sqrt(1.0 - phi));
}
double strut_fraction(double phi) { return 1.0 - std::sqrt(1.0 - phi); }

double strut_aspect_ratio(double phi) { return strut_fraction(phi) / std::sqrt(1.0 - phi); }
double buckling_onset_R(double phi) {
  const double a = strut_aspect_ratio(phi);
  return M_PI * M_PI * a * a / 12.0;
}
double nonreflecting_band_speed(double phi) { return 1.0 / (1.0 - phi); }
double strut_fraction_3d(double phi) { return 1.0 - std::cbrt(1.0 - phi); }
double strut_fraction(double phi, Geometry geometry) {
  return geometry == Geometry::pseudo1d_3d ? strut_fraction_3d(phi) : strut_fraction(phi);
}

namespace random_structure {
double thinnest_strut_fraction(double phi) { return kMinStrut * strut_fraction(phi); }
double area_spread(double phi) {
  if (!(phi < 1.0)) return 0.0;  // the solid column has no voids
  // The largest void, side sqrt((1 + spread)(1 - phi)), leaves the thinnest strut in its cell.
  const double largest = 1.0 - thinnest_strut_fraction(phi);
  return std::min(kAreaSpread, largest * largest / (1.0 - phi) - 1.0);
}
double smallest_void_fraction(double phi) {
  return std::sqrt((1.0 - area_spread(phi)) * (1.0 - phi));
}
}  // namespace random_structure

int SceneParams::grid_cells_per_unit() const {
  if (cells_per_unit > 0) return cells_per_unit;
  const double n = cells_per_strut / strut_fraction();
  if (!(n >= 1.0 && n <= 1e6)) return 0;  // out of range or NaN: validate() says which field
  // The fewest cells that reach cells_per_strut; the tolerance keeps a quotient that is a whole
  // number up to round-off from taking one cell more.
  return static_cast<int>(std::ceil(n - 1e-9));
}

namespace {

using text::num;

// Adds an error unless the range holds v; NaN always fails.
void check_range(std::vector<FieldError>& errors, const char* field, double v, const Range& r) {
  if (!r.contains(v)) errors.push_back({field, "must be in " + to_string(r) + ", got " + num(v)});
}

}  // namespace

bool Range::contains(double v) const {
  return std::isfinite(v) && (open ? (v > lo && v < hi) : (v >= lo && v <= hi));
}

std::string to_string(const Range& r) {
  // whole numbers below 1e7 in full ("1000000", not "1e+06"), the rest to 6 digits
  auto bound = [](double v) {
    return v == std::floor(v) && std::abs(v) < 1e7 ? std::to_string(static_cast<long>(v)) : num(v);
  };
  std::string s = r.open ? "(" : "[";
  s += bound(r.lo);
  s += ", ";
  s += bound(r.hi);
  s += r.open ? ")" : "]";
  return s;
}

namespace {
// The thinnest strut's width [m]: the regular strut, or a random structure's thinnest one.
double thinnest_strut(const SceneParams& p) {
  return p.structure == Structure::random
             ? p.unit_cell() * random_structure::thinnest_strut_fraction(p.phi)
             : p.unit_cell() - p.hole_side();
}
}  // namespace

int regular_void_side(const SceneParams& p, int per_unit) {
  // With an odd count the hole sits half a particle off centre, the same in every cell: a
  // translation of the whole structure.
  const double spacing = p.unit_cell() / per_unit;
  return std::clamp(static_cast<int>(std::lround(p.hole_side() / spacing)), 0, per_unit - 1);
}

double thinnest_strut_cells(const SceneParams& p) {
  return thinnest_strut(p) / p.grid_spacing();
}

namespace {
// What the 3D column (pseudo1d_3d) does not run: the 2D engine's variants and outputs that
// have no 3D counterpart yet.
void validate_3d(const SceneParams& p, std::vector<FieldError>& e) {
  const std::string what = "pseudo1d_3d runs ";
  if (p.transfer != Transfer::apic) e.push_back({"transfer", what + "apic only"});
  if (p.gradient != Gradient::mls) e.push_back({"gradient", what + "mls only"});
  if (p.pore_contact == PoreContact::split_fields) {
    e.push_back({"pore_contact", what + "one velocity field (single_field or auto)"});
  }
  if (p.structure != Structure::regular) e.push_back({"structure", what + "regular only"});
  if (p.perturbation != 0.0) e.push_back({"perturbation", what + "an unperturbed lattice (0)"});
  if (p.movie_d_eps != 0.0) e.push_back({"movie_d_eps", what + "without a movie (0)"});
  if (!p.snapshot_eps.empty()) e.push_back({"snapshot_eps", what + "without snapshots ([])"});
}
}  // namespace

double cfl_time_step(double cfl, double dx, double p_wave_speed, double fastest_speed) {
  return cfl * dx / (p_wave_speed + (std::isfinite(fastest_speed) ? fastest_speed : 0.0));
}

SceneParams scene_defaults(Geometry g) {
  SceneParams p;
  p.geometry = g;
  if (g == Geometry::pseudo1d_3d) {
    p.snapshot_eps.clear();
    p.movie_d_eps = 0.0;
  }
  return p;
}

PoreContact resolved_pore_contact(const SceneParams& p) {
  if (p.pore_contact != PoreContact::automatic) return p.pore_contact;
  const bool allowed = p.geometry != Geometry::pseudo1d_3d && p.transfer == Transfer::apic &&
                       p.gradient == Gradient::mls && p.phi != 1.0 &&
                       thinnest_strut_cells(p) >= kSplitFieldsMinStrutCells;
  return allowed ? PoreContact::split_fields : PoreContact::single_field;
}

std::vector<FieldError> validate(const SceneParams& p) {
  std::vector<FieldError> e;
  check_range(e, "S", p.S, limits::S);
  check_range(e, "R", p.R, limits::R);
  // phi = 1 is the solid column of the verification tests (no holes; needs an explicit eps_end).
  if (p.phi != kSolidColumnPhi) check_range(e, "phi", p.phi, limits::phi);
  if (p.phi == kSolidColumnPhi && !(p.eps_end > 0.0)) {
    e.push_back({"eps_end", "must be set (> 0) for a solid column (phi = 1)"});
  }
  check_range(e, "rho", p.rho, limits::rho);
  check_range(e, "nu", p.nu, limits::nu);
  check_range(e, "q_y", p.q_y, limits::q_y);
  check_range(e, "h0", p.h0, limits::h0);
  check_range(e, "n_cols", p.n_cols, limits::n_cols);
  check_range(e, "n_rows", p.n_rows, limits::n_rows);
  if (p.cells_per_unit != 0) {
    check_range(e, "cells_per_unit", p.cells_per_unit, limits::cells_per_unit);
  }
  check_range(e, "cells_per_strut", p.cells_per_strut, limits::cells_per_strut);
  check_range(e, "particles_per_cell", p.particles_per_cell, limits::particles_per_cell);
  check_range(e, "cfl", p.cfl, limits::cfl);
  check_range(e, "flip_ratio", p.flip_ratio, limits::flip_ratio);
  check_range(e, "perturbation", p.perturbation, limits::perturbation);
  check_range(e, "d_eps", p.d_eps, limits::d_eps);
  check_range(e, "threads", p.threads, limits::threads);
  if (p.eps_end > 0.0 || !std::isfinite(p.eps_end)) {
    // eps_end <= 0 means "until fully dense"; a strain beyond 1 - phi would crush solid matter.
    check_range(e, "eps_end", p.eps_end, limits::eps_end);
    if (p.phi != kSolidColumnPhi && limits::phi.contains(p.phi) && p.eps_end > 1.0 - p.phi + 1e-12) {
      e.push_back({"eps_end", "must be at most 1 - phi = " + num(1.0 - p.phi) +
                                  " (full density; beyond it the column crushes solid matter), got " +
                                  num(p.eps_end)});
    }
  }
  if (p.snapshot_eps.size() > kMaxSnapshots) {
    e.push_back({"snapshot_eps", "at most " + num(kMaxSnapshots) + " snapshots, got " +
                                     num(p.snapshot_eps.size())});
  }
  for (double s : p.snapshot_eps) check_range(e, "snapshot_eps", s, limits::snapshot_eps);
  if (p.movie_d_eps != 0.0) {  // 0: no movie; a movie frame needs an output frame to fall on
    if (!limits::movie_d_eps.contains(p.movie_d_eps)) {
      check_range(e, "movie_d_eps", p.movie_d_eps, limits::movie_d_eps);
    } else if (p.movie_d_eps < p.d_eps) {
      e.push_back({"movie_d_eps", "must be 0 (no movie) or at least d_eps (" + num(p.d_eps) +
                                      "), got " + num(p.movie_d_eps)});
    }
  }
  if (p.geometry == Geometry::pseudo1d_3d) validate_3d(p, e);
  if (e.empty() && p.eps_final() / p.d_eps > 1e5) {
    e.push_back({"d_eps", "too small: " + num(p.eps_final() / p.d_eps) +
                              " frames up to eps_end, at most 1e5"});
  }
  if (e.empty() && p.cells_per_unit == 0 &&
      !limits::cells_per_unit.contains(p.grid_cells_per_unit())) {
    e.push_back({"cells_per_strut", num(p.cells_per_strut) + " cells across the strut at phi = " +
                                        num(p.phi) + " take " +
                                        num(p.cells_per_strut / p.strut_fraction()) +
                                        " cells per unit cell, outside " +
                                        to_string(limits::cells_per_unit)});
  }
  if (e.empty()) {
    // Thin features must still be resolved: the hole and the strut need a grid cell each.
    const int cells_per_unit = p.grid_cells_per_unit();
    const char* field = p.cells_per_unit != 0 ? "cells_per_unit" : "cells_per_strut";
    const double dx = p.grid_spacing();
    // A random structure's smallest void and thinnest strut (random_structure) count.
    const bool random = p.structure == Structure::random;
    const double hole = random ? p.unit_cell() * random_structure::smallest_void_fraction(p.phi)
                               : p.hole_side();
    const double strut = thinnest_strut(p);
    if (p.phi != 1.0 && (hole < dx || strut < dx)) {
      e.push_back({field, std::string("too coarse for ") + (random ? "a random structure at " : "") +
                              "phi = " + num(p.phi) + ": " + (random ? "smallest hole " : "hole ") +
                              num(hole / dx) + " and " + (random ? "thinnest strut " : "strut ") +
                              num(strut / dx) + " grid cells, need >= 1 each"});
    }
    if (p.pore_contact == PoreContact::split_fields) {
      if (p.transfer != Transfer::apic || p.gradient != Gradient::mls) {
        e.push_back({"pore_contact", "split_fields needs transfer = apic and gradient = mls"});
      }
      if (p.phi != 1.0 && strut / dx < kSplitFieldsMinStrutCells) {
        e.push_back({"pore_contact", std::string("split_fields needs at least ") +
                                         num(kSplitFieldsMinStrutCells) + " grid cells across " +
                                         (random ? "the thinnest strut" : "the strut") + ", got " +
                                         num(strut / dx) + " (raise " + field + ")"});
      }
    }
    const double across = p.geometry == Geometry::pseudo1d_3d
                              ? static_cast<double>(cells_per_unit) * cells_per_unit
                              : p.cols() * cells_per_unit + 5;
    const double nodes = across * (p.n_rows * cells_per_unit + 5);
    if (nodes > 2e7) {
      e.push_back({field, "grid of " + num(nodes) + " nodes exceeds the limit of 2e7"});
    }
  }
  return e;
}

const char* to_string(Geometry g) {
  switch (g) {
    case Geometry::pseudo1d: return "pseudo1d";
    case Geometry::full2d: return "full2d";
    case Geometry::pseudo1d_3d: return "pseudo1d_3d";
  }
  return "?";
}
const char* to_string(Transfer t) { return t == Transfer::apic ? "apic" : "pic_flip"; }
const char* to_string(PlateContact c) {
  return c == PlateContact::bonded ? "bonded" : "unilateral";
}

const char* to_string(Gradient g) { return g == Gradient::mls ? "mls" : "bspline"; }
const char* to_string(Structure s) { return s == Structure::regular ? "regular" : "random"; }

bool parse(const std::string& s, Structure& out) {
  if (s == "regular") return out = Structure::regular, true;
  if (s == "random") return out = Structure::random, true;
  return false;
}

bool parse(const std::string& s, Gradient& out) {
  if (s == "mls") return out = Gradient::mls, true;
  if (s == "bspline") return out = Gradient::bspline, true;
  return false;
}

bool parse(const std::string& s, Geometry& out) {
  if (s == "pseudo1d") return out = Geometry::pseudo1d, true;
  if (s == "full2d") return out = Geometry::full2d, true;
  if (s == "pseudo1d_3d") return out = Geometry::pseudo1d_3d, true;
  return false;
}
bool parse(const std::string& s, Transfer& out) {
  if (s == "apic") return out = Transfer::apic, true;
  if (s == "pic_flip") return out = Transfer::pic_flip, true;
  return false;
}
const char* to_string(PoreContact c) {
  switch (c) {
    case PoreContact::single_field: return "single_field";
    case PoreContact::split_fields: return "split_fields";
    case PoreContact::automatic: return "auto";
  }
  return "?";
}
bool parse(const std::string& s, PoreContact& out) {
  if (s == "single_field") return out = PoreContact::single_field, true;
  if (s == "split_fields") return out = PoreContact::split_fields, true;
  if (s == "auto") return out = PoreContact::automatic, true;
  return false;
}

bool parse(const std::string& s, PlateContact& out) {
  if (s == "bonded") return out = PlateContact::bonded, true;
  if (s == "unilateral") return out = PlateContact::unilateral, true;
  return false;
}

}  // namespace compaction
