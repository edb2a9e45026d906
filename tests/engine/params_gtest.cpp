// Scene parameters: derived quantities, validation messages naming the field, strict JSON.
#include <gtest/gtest.h>

#include <cmath>

#include "compaction/params.hpp"
#include "compaction/params_json.hpp"

namespace compaction {
namespace {

bool has_error(const std::vector<FieldError>& errors, const std::string& field) {
  for (const auto& e : errors)
    if (e.field == field) return true;
  return false;
}

TEST(ParamsGtest, DerivedQuantitiesFollowFromSRAndPhi) {
  SceneParams p;
  p.S = 4e-3, p.R = 1e-5, p.phi = 0.4;
  EXPECT_DOUBLE_EQ(p.youngs_modulus(), 250.0 / 1e-5);
  EXPECT_DOUBLE_EQ(p.plate_speed(), 4e-3 * std::sqrt(2.5e7 / 1000.0));
  // c_P / sqrt(E / rho) = sqrt((1 - nu) / ((1 + nu)(1 - 2 nu))) = 1.16024 at nu = 0.3
  EXPECT_NEAR(p.p_wave_speed() / p.bar_wave_speed(), 1.1602387, 1e-7);
  EXPECT_NEAR(p.hole_side(), (1.0 / 34) * std::sqrt(0.6), 1e-15);
  EXPECT_DOUBLE_EQ(p.eps_final(), 0.6);
  EXPECT_TRUE(validate(p).empty());
}

TEST(ParamsGtest, OutOfRangeValuesAreRejectedWithTheirField) {
  SceneParams p;
  p.phi = 0.9, p.S = 0.0, p.R = 1.5, p.cells_per_unit = 1, p.threads = 0;
  const auto e = validate(p);
  for (const char* f : {"phi", "S", "R", "cells_per_unit", "threads"}) {
    EXPECT_TRUE(has_error(e, f)) << f;
  }
  p = SceneParams{};
  p.S = std::nan("");
  ASSERT_TRUE(has_error(validate(p), "S"));
  EXPECT_NE(validate(p)[0].message.find("got nan"), std::string::npos);
}

TEST(ParamsGtest, TooCoarseGridForTheStructureIsRejected) {
  SceneParams p;
  p.phi = 0.8, p.cells_per_unit = 3;  // strut = L (1 - sqrt(0.2)) = 0.55 L = 1.7 cells: ok
  EXPECT_TRUE(validate(p).empty());
  p.phi = 0.25, p.cells_per_unit = 4;  // strut = 0.134 L = 0.54 cells: unresolved
  EXPECT_TRUE(has_error(validate(p), "cells_per_unit"));
}

// A random structure's struts may thin to kMinStrut = 1/2 of the regular one, which must keep a
// grid cell: 2.5 cells across the regular strut pass, 1.8 (the fast preset) do not.
TEST(ParamsGtest, RandomStructureNeedsItsThinnestStrutResolved) {
  SceneParams p;
  p.structure = Structure::random, p.cells_per_strut = 2.5;
  EXPECT_TRUE(validate(p).empty());
  p.cells_per_strut = 1.8;
  const auto e = validate(p);
  ASSERT_TRUE(has_error(e, "cells_per_strut"));
  EXPECT_NE(e[0].message.find("thinnest strut"), std::string::npos) << e[0].message;
  p.structure = Structure::regular;
  EXPECT_TRUE(validate(p).empty());
}

// split_fields runs APIC with the MLS gradient only, and needs kSplitFieldsMinStrutCells (3)
// cells across the thinnest strut, so that no node reaches both faces of a strut.
TEST(ParamsGtest, SplitFieldsNeedApicMlsAndThreeCellsAcrossTheStrut) {
  SceneParams p;
  p.pore_contact = PoreContact::split_fields;
  EXPECT_TRUE(validate(p).empty());  // the default preset's 4.5 cells
  p.cells_per_strut = 3.0;
  EXPECT_TRUE(validate(p).empty());
  p.cells_per_unit = 12;  // 2.7 cells across the strut at phi = 0.4
  auto e = validate(p);
  ASSERT_TRUE(has_error(e, "pore_contact"));
  EXPECT_NE(e[0].message.find("cells_per_unit"), std::string::npos) << e[0].message;
  p.cells_per_unit = 0;
  p.structure = Structure::random;  // the thinnest strut is half the regular one: 2.25 cells
  EXPECT_TRUE(has_error(validate(p), "pore_contact"));
  p.structure = Structure::regular, p.transfer = Transfer::pic_flip;
  EXPECT_TRUE(has_error(validate(p), "pore_contact"));
  p.transfer = Transfer::apic, p.gradient = Gradient::bspline;
  EXPECT_TRUE(has_error(validate(p), "pore_contact"));
  p.pore_contact = PoreContact::single_field;
  EXPECT_TRUE(validate(p).empty());
}

// auto is split_fields exactly where split_fields would be valid, else single_field, and is
// itself always valid; a scene reports what it resolves to (resolved_pore_contact).
TEST(ParamsGtest, AutoPoreContactSplitsWhereTheGridResolvesTheThinnestStrut) {
  SceneParams p;
  p.pore_contact = PoreContact::automatic;
  const auto resolved_and_valid = [&] {
    const auto e = validate(p);
    EXPECT_TRUE(e.empty()) << e.front().field << ": " << e.front().message;
    return resolved_pore_contact(p);
  };
  EXPECT_EQ(resolved_and_valid(), PoreContact::split_fields);  // 4.5 cells across the strut
  p.cells_per_unit = 13;                                       // 2.94 cells
  EXPECT_EQ(resolved_and_valid(), PoreContact::single_field);
  p.cells_per_unit = 14;                                       // 3.14 cells
  EXPECT_EQ(resolved_and_valid(), PoreContact::split_fields);
  p.cells_per_unit = 0;
  p.structure = Structure::random;  // the thinnest strut: half the regular one, 2.25 cells
  EXPECT_EQ(resolved_and_valid(), PoreContact::single_field);
  p.cells_per_strut = 6.0;  // 3 cells across the thinnest random strut
  EXPECT_EQ(resolved_and_valid(), PoreContact::split_fields);
  p.transfer = Transfer::pic_flip;
  EXPECT_EQ(resolved_and_valid(), PoreContact::single_field);
  p.transfer = Transfer::apic, p.gradient = Gradient::bspline;
  EXPECT_EQ(resolved_and_valid(), PoreContact::single_field);
  p.gradient = Gradient::mls, p.phi = kSolidColumnPhi, p.eps_end = 0.01;  // no pores to close
  EXPECT_EQ(resolved_and_valid(), PoreContact::single_field);
  for (PoreContact c : {PoreContact::single_field, PoreContact::split_fields}) {
    p.pore_contact = c;  // an explicit choice is kept (validate() refuses what cannot run)
    EXPECT_EQ(resolved_pore_contact(p), c);
  }
  PoreContact parsed{};
  ASSERT_TRUE(parse("auto", parsed));
  EXPECT_EQ(parsed, PoreContact::automatic);
  EXPECT_STREQ(to_string(PoreContact::automatic), "auto");
}

// The spread of the void areas: kAreaSpread where the largest void leaves kMinStrut of the
// regular strut, less at low phi; the largest void then leaves exactly that strut.
TEST(ParamsGtest, RandomVoidAreaSpreadKeepsTheThinnestStrut) {
  EXPECT_EQ(random_structure::area_spread(0.4), random_structure::kAreaSpread);
  EXPECT_EQ(random_structure::area_spread(0.75), random_structure::kAreaSpread);
  for (double phi : {0.2, 0.25, 0.3}) {
    const double w = random_structure::area_spread(phi);
    EXPECT_GT(w, 0.05) << phi;
    EXPECT_LT(w, random_structure::kAreaSpread) << phi;
    const double largest = std::sqrt((1.0 + w) * (1.0 - phi));
    EXPECT_NEAR(1.0 - largest, random_structure::thinnest_strut_fraction(phi), 1e-12) << phi;
  }
  EXPECT_NEAR(random_structure::thinnest_strut_fraction(0.4), 0.5 * (1 - std::sqrt(0.6)), 1e-15);
  EXPECT_NEAR(random_structure::smallest_void_fraction(0.4), std::sqrt(0.7 * 0.6), 1e-15);
}

TEST(ParamsGtest, TheGridPutsAtLeastCellsPerStrutAcrossTheThinnestStrut) {
  SceneParams p;  // 4.5 cells across the strut, no cells_per_unit
  p.phi = 0.4;    // strut 1 - sqrt(0.6) = 0.2254 of the unit cell: 4.5 / 0.2254 = 19.96
  EXPECT_EQ(p.grid_cells_per_unit(), 20);
  EXPECT_NEAR(p.grid_cells_per_strut(), 20 * (1 - std::sqrt(0.6)), 1e-15);
  p.phi = 0.25;   // strut 0.134: 33.6 -> 34 cells per unit cell
  EXPECT_EQ(p.grid_cells_per_unit(), 34);
  p.phi = 0.75;   // strut 0.5: exactly 9, which round-off must not turn into 10
  EXPECT_EQ(p.grid_cells_per_unit(), 9);
  p.cells_per_unit = 12;  // the override wins
  EXPECT_EQ(p.grid_cells_per_unit(), 12);
  EXPECT_DOUBLE_EQ(p.grid_cells_per_strut(), 6.0);
}

TEST(ParamsGtest, CellsPerStrutOutsideItsRangeOrTheGridsIsRejectedWithItsField) {
  SceneParams p;
  p.cells_per_strut = 0.5;
  EXPECT_TRUE(has_error(validate(p), "cells_per_strut"));
  p.cells_per_strut = 40.0, p.phi = 0.25;  // 40 / 0.134 = 298 cells per unit cell, above 200
  ASSERT_TRUE(has_error(validate(p), "cells_per_strut"));
  EXPECT_NE(validate(p)[0].message.find("cells per unit cell"), std::string::npos)
      << validate(p)[0].message;
  p.cells_per_unit = 100;  // an override within its range makes cells_per_strut moot
  EXPECT_TRUE(validate(p).empty());
}

TEST(ParamsGtest, SolidColumnNeedsAnExplicitEndStrain) {
  SceneParams p;
  p.phi = 1.0;
  EXPECT_TRUE(has_error(validate(p), "eps_end"));
  p.eps_end = 0.01;
  EXPECT_TRUE(validate(p).empty());
}

TEST(ParamsGtest, EndStrainStopsAtFullDensity) {
  SceneParams p;
  p.phi = 0.4;
  p.eps_end = 0.6;  // full density, as the solid-fraction studies run
  EXPECT_TRUE(validate(p).empty());
  p.eps_end = 0.61;  // within the range of eps_end, but it would crush the solid struts
  ASSERT_TRUE(has_error(validate(p), "eps_end"));
  EXPECT_NE(validate(p)[0].message.find("1 - phi = 0.6"), std::string::npos) << validate(p)[0].message;
  p.phi = 0.3;  // 1 - phi = 0.7: the same strain is allowed at a lower solid fraction
  EXPECT_TRUE(validate(p).empty());
}

TEST(ParamsGtest, JsonRoundTripKeepsEveryField) {
  SceneParams p;
  p.S = 0.02, p.R = 3e-4, p.phi = 0.55, p.geometry = Geometry::full2d, p.n_cols = 5;
  p.transfer = Transfer::pic_flip, p.contact = PlateContact::unilateral, p.seed = 77;
  p.gradient = Gradient::bspline, p.structure = Structure::random;
  p.snapshot_eps = {0.1, 0.3};
  SceneParams q;
  ASSERT_TRUE(from_json(to_json(p), q).empty());
  EXPECT_EQ(to_json(q), to_json(p));
  SceneParams split;  // split_fields needs apic and mls (validate())
  split.pore_contact = PoreContact::split_fields;
  ASSERT_TRUE(from_json(to_json(split), q).empty());
  EXPECT_EQ(q.pore_contact, PoreContact::split_fields);
  EXPECT_EQ(to_json(q), to_json(split));
}

// pseudo1d_3d: phi is a volume fraction, so the cubic hole's side is L (1 - phi)^(1/3) and the
// strut L (1 - (1 - phi)^(1/3)); the grid and the coarseness check follow them; the name
// round-trips through to_string / parse and JSON.
TEST(ParamsGtest, Pseudo1d3dHasCubicHolesAndRoundTrips) {
  SceneParams p;
  p.geometry = Geometry::pseudo1d_3d, p.phi = 0.4, p.movie_d_eps = 0.0, p.snapshot_eps = {};
  EXPECT_NEAR(p.hole_side(), (1.0 / 34) * std::cbrt(0.6), 1e-15);
  EXPECT_NEAR(p.strut_fraction(), 1.0 - std::cbrt(0.6), 1e-15);
  EXPECT_EQ(p.cols(), 1);
  EXPECT_DOUBLE_EQ(p.width(), p.unit_cell());
  // 4.5 cells across a strut of 0.1566 L: ceil(28.7) = 29 cells per unit cell
  EXPECT_EQ(p.grid_cells_per_unit(), 29);
  EXPECT_TRUE(validate(p).empty());
  EXPECT_EQ(resolved_pore_contact(p), PoreContact::single_field);  // auto: one field in 3D
  Geometry g;
  ASSERT_TRUE(parse(to_string(p.geometry), g));
  EXPECT_EQ(g, Geometry::pseudo1d_3d);
  SceneParams q;
  ASSERT_TRUE(from_json(to_json(p), q).empty());
  EXPECT_EQ(to_json(q), to_json(p));
  // strut 0.157 L = 0.47 cells at 3 cells per unit cell: too coarse (in 2D, 0.23 L = 0.68)
  p.cells_per_unit = 3;
  EXPECT_TRUE(has_error(validate(p), "cells_per_unit"));
  p.phi = 0.8, p.cells_per_unit = 2;  // hole 0.585 L = 1.17 cells, strut 0.83 cells
  EXPECT_TRUE(has_error(validate(p), "cells_per_unit"));
  p.cells_per_unit = 3;  // hole 1.75, strut 1.25 cells: resolved
  EXPECT_TRUE(validate(p).empty());
}

// What the 3D column does not run is refused by name, not ignored.
TEST(ParamsGtest, Pseudo1d3dRefusesWhatItDoesNotRun) {
  SceneParams p;
  p.geometry = Geometry::pseudo1d_3d;  // with the default movie and snapshot
  auto e = validate(p);
  EXPECT_TRUE(has_error(e, "movie_d_eps"));
  EXPECT_TRUE(has_error(e, "snapshot_eps"));
  p.movie_d_eps = 0.0, p.snapshot_eps = {};
  p.transfer = Transfer::pic_flip, p.gradient = Gradient::bspline, p.threads = 2;
  p.pore_contact = PoreContact::split_fields, p.structure = Structure::random;
  p.perturbation = 0.1;
  e = validate(p);
  for (const char* f : {"transfer", "gradient", "pore_contact", "structure", "perturbation"}) {
    EXPECT_TRUE(has_error(e, f)) << f;
  }
  EXPECT_FALSE(has_error(e, "threads")) << "the 3D column runs on threads as 2D does";
}

TEST(ParamsGtest, JsonReadingIsStrict) {
  SceneParams p;
  auto e = from_json(nlohmann::json::parse(R"({"S": "fast", "phii": 0.4, "n_rows": 3.5})"), p);
  EXPECT_TRUE(has_error(e, "S"));
  EXPECT_TRUE(has_error(e, "phii"));
  EXPECT_TRUE(has_error(e, "n_rows"));
  e = from_json(nlohmann::json::parse(R"({"geometry": "3d"})"), p);
  ASSERT_TRUE(has_error(e, "geometry"));
  e = from_json(nlohmann::json::parse(R"({"structure": "voronoi"})"), p);
  ASSERT_TRUE(has_error(e, "structure"));
  EXPECT_NE(e[0].message.find("\"regular\" or \"random\""), std::string::npos) << e[0].message;
  e = from_json(nlohmann::json::parse(R"({"pore_contact": "penalty"})"), p);
  ASSERT_TRUE(has_error(e, "pore_contact"));
  EXPECT_NE(e[0].message.find("\"single_field\", \"split_fields\" or \"auto\""), std::string::npos)
      << e[0].message;
  e = from_json(nlohmann::json::parse(R"([1, 2])"), p);
  EXPECT_EQ(e.size(), 1u);
  e = from_json(nlohmann::json::parse(R"({"phi": 0.95})"), p);
  EXPECT_TRUE(has_error(e, "phi"));
}

}  // namespace
}  // namespace compaction
