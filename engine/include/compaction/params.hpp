// Scene parameters of one compaction run: the dimensionless inputs (S, R, phi), the fixed
// material constants, the geometry and the numerics. This is the engine's public input type;
// the server and the worker see the engine only through it and through result.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace compaction {

enum class Geometry {
  pseudo1d,  // one unit cell wide, periodic in x by index wrapping (the workhorse of sweeps)
  full2d,    // n_cols x n_rows cells between frictionless side walls
  pseudo1d_3d,  // 3D: one unit cell across in x and z (periodic in both), n_rows tall, cubic
                // holes of side L (1 - phi)^(1/3); phi is a volume fraction. APIC with MLS, a
                // regular structure, one thread, no movie or snapshots (validate() says so)
};

enum class Transfer {
  apic,     // affine particle-in-cell (default): conserves linear and angular momentum
  pic_flip  // blend: v_p = flip_ratio * FLIP + (1 - flip_ratio) * PIC
};

// How the stress divergence (P2G force) and the velocity gradient (Fe update) are formed.
enum class Gradient {
  mls,     // moving least squares (Hu et al. 2018): grad w ~ 4 w (x_i - x_p) / dx^2 (default)
  bspline  // the exact gradient of the B-spline weights, for both (standard MPM, as Matter)
};

// The voids of the specimen (docs/engine.md, "Random structures").
enum class Structure {
  regular,  // every unit cell has the same centred square void of side L sqrt(1 - phi)
  random    // each void's area and centre drawn from `seed` (random_structure below)
};

enum class PlateContact {
  bonded,     // plates impose their normal velocity on the nodes they cover (no separation)
  unilateral  // plates only push: the material may separate from a plate
};

// How the faces of a pore interact on the grid as it closes (docs/engine.md, "Pore contact").
enum class PoreContact {
  single_field,  // one velocity field: faces interact once they share grid nodes, a cell or two
                 // before the solid meets
  split_fields,  // two fields where faces of opposite normals share a node, merged once the
                 // node is full (the gap closed); APIC with the MLS gradient only
  automatic      // "auto": split_fields where the scene allows it (APIC with MLS, at least
                 // kSplitFieldsMinStrutCells across the thinnest strut), else single_field
};

// Limits of validate() that other components serve or check against.
inline constexpr double kPhiMin = 0.2;          // porous structures: solid fraction range
inline constexpr double kPhiMax = 0.8;
// The solid fractions the paper's classification holds for ("between approximately 0.25 and
// 0.75"): the engine runs the wider range above, the map of a solid fraction outside this one
// is the model's extrapolation.
inline constexpr double kModelPhiMin = 0.25;
inline constexpr double kModelPhiMax = 0.75;
inline constexpr double kSolidColumnPhi = 1.0;  // no holes: the verification tests' column
inline constexpr std::size_t kMaxSnapshots = 100;
// split_fields assumes that no grid node reaches both faces of one strut: a quadratic B-spline
// reaches 1.5 cells to each side, so the thinnest strut needs 3 cells. (Else the two halves of
// a strut could be told apart at a node as if a gap lay between them.)
inline constexpr double kSplitFieldsMinStrutCells = 3.0;

// An interval a parameter must lie in: [lo, hi], or (lo, hi) when open.
struct Range {
  double lo, hi;
  bool open = false;
  bool contains(double v) const;  // false for NaN
};
std::string to_string(const Range& r);  // "[0.2, 0.8]", "(0, 1)"

// The range of each field that validate() checks, in one place: validate() and the runner's
// --help read them.
namespace limits {
inline constexpr Range S{0.0, 1.0, true};
inline constexpr Range R{0.0, 1.0, true};
inline constexpr Range phi{kPhiMin, kPhiMax};  // or kSolidColumnPhi
inline constexpr Range rho{1e-6, 1e9};
inline constexpr Range nu{0.0, 0.49};
inline constexpr Range q_y{1e-9, 1e15};
inline constexpr Range h0{1e-9, 1e9};
inline constexpr Range n_cols{1, 200};
inline constexpr Range n_rows{1, 400};
inline constexpr Range cells_per_unit{2, 200};     // when set (> 0); 0 means from cells_per_strut
inline constexpr Range cells_per_strut{1.0, 50.0};
inline constexpr Range particles_per_cell{1, 4};
inline constexpr Range cfl{0.0, 2.0, true};
inline constexpr Range flip_ratio{0.0, 1.0};
inline constexpr Range perturbation{0.0, 0.5};
inline constexpr Range d_eps{1e-8, 0.1};
inline constexpr Range threads{1, 256};
inline constexpr Range eps_end{0.0, 0.95, true};  // when set (> 0); <= 0 means 1 - phi
inline constexpr Range snapshot_eps{0.0, 0.95};
inline constexpr Range movie_d_eps{0.001, 0.5};  // when set (> 0); 0: no movie; and >= d_eps
}  // namespace limits

// The thinnest strut between two square holes of a regular structure of solid fraction phi, as
// a fraction of the unit cell: 1 - sqrt(1 - phi) (1 for the solid column, phi = 1).
double strut_fraction(double phi);
// The same between two cubic holes of a 3D structure: 1 - (1 - phi)^(1/3).
double strut_fraction_3d(double phi);
// The thinnest strut of a geometry's regular structure: the cubic holes' of the 3D column, the
// square holes' of the 2D ones.
double strut_fraction(double phi, Geometry geometry);

// What the model predicts from phi alone (the paper), served with the phase map:
// the struts' aspect ratio a = t / l, thickness over length, (1 - sqrt(1 - phi)) / sqrt(1 - phi);
double strut_aspect_ratio(double phi);
// the buckling onset R_crit ~ pi^2 a^2 / 12 (Euler buckling of a strut before it yields);
double buckling_onset_R(double phi);
// the speed of a non-reflecting band, c_b / V = 1 / (1 - phi) (mass balance: dense behind it).
double nonreflecting_band_speed(double phi);

// The distribution of the voids of a random structure, the rule build_scene() follows and
// validate() checks. Each unit cell keeps one square void, whose area is drawn uniformly in
// L^2 (1 - phi) [1 - spread, 1 + spread], in antithetic pairs (u, 2 - u) dealt to the cells in a
// seeded random order, so that the areas add up to those of the regular structure and the
// realised phi differs from phi only by the particle lattice. Its centre moves from the cell's
// centre by a uniform offset in x and in y, up to what keeps half of kMinStrut times the
// regular strut between the void and its cell's edges: two neighbouring voids leave at least
// that strut between them, and the bottom and top rows keep solid on the plates.
namespace random_structure {
inline constexpr double kAreaSpread = 0.3;  // half-width of the uniform void area, / mean  [-]
inline constexpr double kMinStrut = 0.5;    // thinnest strut, / the regular strut         [-]
// The spread at phi: kAreaSpread, or less where the largest void would leave a strut thinner
// than kMinStrut times the regular one (below phi ~ 0.39).
double area_spread(double phi);
// The thinnest strut and the smallest void side, as fractions of the unit cell.
double thinnest_strut_fraction(double phi);
double smallest_void_fraction(double phi);
}  // namespace random_structure

struct SceneParams {
  // Dimensionless inputs (the paper's Eq. 3).
  double S = 4e-3;    // Mach number V / sqrt(E / rho)                          [-]
  double R = 1e-5;    // relative strength q_y / E                               [-]
  double phi = 0.4;   // solid area fraction, [0.2, 0.8]; 1 = solid column (tests) [-]

  // Material constants; only S, R and phi change the dimensionless result.
  double rho = 1000.0;  // density of the solid                                   [kg/m^2]
  double nu = 0.3;      // Poisson's ratio                                        [-]
  double q_y = 250.0;   // von Mises yield strength, sqrt(3/2 s:s) <= q_y         [N/m]
  double h0 = 1.0;      // initial specimen height (only scales time)            [m]

  // Geometry.
  Geometry geometry = Geometry::pseudo1d;
  int n_cols = 17;  // unit cells across (full2d only; pseudo1d always has one)  [-]
  int n_rows = 34;  // unit cells along the compression axis                     [-]
  Structure structure = Structure::regular;  // the voids: regular or random (from seed)

  // Numerics. The grid is given by the cells across the thinnest strut, so that one setting
  // means the same accuracy at every phi; cells_per_unit overrides it when set.
  double cells_per_strut = 4.5; // at least this many grid cells across a strut   [-]
  int cells_per_unit = 0;       // > 0: grid cells along a unit cell's side, overriding
                                // cells_per_strut; 0: the fewest that give cells_per_strut [-]
  int particles_per_cell = 2;   // particles per grid cell per direction (2 -> 2x2) [-]
  double cfl = 0.5;             // dt = cfl * dx / (c_P + max particle speed)    [-]
  Transfer transfer = Transfer::apic;
  double flip_ratio = 0.95;     // FLIP share of the pic_flip blend               [-]
  Gradient gradient = Gradient::mls;
  PlateContact contact = PlateContact::bonded;
  PoreContact pore_contact = PoreContact::automatic;  // the default preset's (presets.hpp)
  double perturbation = 0.0;    // random particle offset, fraction of spacing    [-]
  std::uint64_t seed = 1;       // seed of the perturbation and the random structure [-]

  // Run control and outputs.
  double eps_end = -1.0;        // final imposed strain V t / h0; <= 0: fully dense, 1 - phi
  double d_eps = 0.002;         // strain between output frames                   [-]
  std::vector<double> snapshot_eps = {0.2};  // strains of particle snapshots     [-]
  double movie_d_eps = 0.02;    // strain between the frames of the movie (movie.hpp; 30 frames
                                // to eps = 0.6, about 3.3 MB at the default preset); 0: none [-]
  int threads = 1;              // worker threads of the time step                [-]

  // Derived quantities.
  double eps_final() const { return eps_end > 0.0 ? eps_end : 1.0 - phi; }
  double youngs_modulus() const { return q_y / R; }                      // E  [N/m]
  double lame_lambda() const;                                             //    [N/m]
  double lame_mu() const;                                                 //    [N/m]
  double bar_wave_speed() const;     // sqrt(E / rho), the speed S is measured with [m/s]
  double p_wave_speed() const;       // sqrt((lambda + 2 mu) / rho)             [m/s]
  double plate_speed() const { return S * bar_wave_speed(); }             // V  [m/s]
  double unit_cell() const { return h0 / n_rows; }                        // L  [m]
  double hole_side() const;          // L sqrt(1 - phi); pseudo1d_3d: L (1 - phi)^(1/3) [m]
  double strut_fraction() const { return compaction::strut_fraction(phi, geometry); }
  int grid_cells_per_unit() const;   // cells_per_unit, or derived from cells_per_strut [-]
  double grid_spacing() const { return unit_cell() / grid_cells_per_unit(); }  // dx   [m]
  double grid_cells_per_strut() const { return grid_cells_per_unit() * strut_fraction(); }
  int cols() const { return geometry == Geometry::full2d ? n_cols : 1; }
  double width() const { return cols() * unit_cell(); }  // (pseudo1d_3d: also the depth) [m]
};

// One problem with one field of the parameters, e.g. {"phi", "must be in [0.2, 0.8], got 0.9"}.
struct FieldError {
  std::string field;
  std::string message;
};

// Every problem with the parameters (empty when they are valid). The limits are those of the
// model's validity and of what a run can afford; the messages name the field and the value.
std::vector<FieldError> validate(const SceneParams& p);

// The explicit time step of the CFL condition: cfl dx / (c_P + the fastest particle's speed),
// the one rule the 2D and 3D steps and the service's cost model use. A speed that is not finite
// counts as 0: the stability checks stop such a run after its step.
double cfl_time_step(double cfl, double dx, double p_wave_speed, double fastest_speed);

// The defaults of a scene of geometry g: SceneParams' own, but for what g cannot take (the 3D
// column runs without snapshots and without a movie). from_json gives a scene whose JSON names
// its geometry these defaults for the keys it leaves out.
SceneParams scene_defaults(Geometry g);

// The side of a regular structure's hole in particles, on a lattice of per_unit particles along
// a unit cell's side (spacing L / per_unit): the count nearest hole_side(), at most per_unit - 1,
// so that the particles represent phi as closely as the lattice allows (centring the hole
// instead would force an even count and could miss phi by 10 %). The scene builders (2D and 3D)
// and the cost model's particle count read it.
int regular_void_side(const SceneParams& p, int per_unit);

// Grid cells across the thinnest strut of the scene (a random structure's thinnest one).
double thinnest_strut_cells(const SceneParams& p);
// The pore contact a scene runs with: single_field or split_fields (auto resolved).
PoreContact resolved_pore_contact(const SceneParams& p);

const char* to_string(Geometry g);
const char* to_string(Transfer t);
const char* to_string(PlateContact c);
const char* to_string(PoreContact c);
const char* to_string(Structure s);
const char* to_string(Gradient g);
bool parse(const std::string& s, Geometry& out);
bool parse(const std::string& s, Transfer& out);
bool parse(const std::string& s, PlateContact& out);
bool parse(const std::string& s, PoreContact& out);
bool parse(const std::string& s, Structure& out);
bool parse(const std::string& s, Gradient& out);

}  // namespace compaction
