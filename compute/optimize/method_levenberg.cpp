// Levenberg-Marquardt on the far field (--method levenberg, and auto's first run beyond a
// handful of free parameters). The metric is a sum of squares over far-field cells (l2:
// lumens; candela_l2: lumens weighted by w_i, farfield.hpp), so the search models the far
// field itself rather than its distance: the residual r(x) = sqrt(w) (F(x) - D) and its
// Jacobian J by central differences (each coordinate moved two lattice steps either way:
// 2 candidates per coordinate, traced as batches with the stage's rays), then the damped
// Gauss-Newton step (J^T J + lambda diag(J^T J)) dc = -J^T r (Marquardt's scaling).
//
// Coarse to fine twice over, both measured on the 36-height freeform (docs/optimization.md):
//  - in shape: where a height grid is free, the coordinates are its cosine modes
//    (height_modes.hpp) and the search frees them by degree kx + ky, the tilts first, the
//    finest last. A surface whose broad shape is wrong sends light to wrong places that
//    no fine ripple mends: from the flat start, all 36 heights at once end 2.6 x the noise
//    floor; freed by degree, 1.00-1.05 x;
//  - in angle: the model's residual is taken on the stage's far field in blocks of cells,
//    coarse then finer, as coarse as the rays need (model_grids): a step moves light by a
//    few degrees, which a 1 degree Jacobian of 1e5 rays sees as noise and a 4 degree one as
//    a trend.
// A step is judged by the search's own score (the metric on the stage's grid, with the
// smoothness weight), not by the model's residual as MINPACK's lmder (Eigen's unsupported
// LevenbergMarquardt) judges it: with its rule on the coarse residual the same start
// stopped after one iteration. Each iteration traces its trial steps together (several
// damping values in one batch, the best kept). Steps are continuous, as BOBYQA's are; the
// search ends where no step moves a parameter by a tenth of its lattice step.
#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "methods.hpp"
#include "optimize/height_modes.hpp"

namespace fird {

namespace {

// Damping values tried together per iteration: lambda 4^-2 .. 4^3 around the last one kept.
constexpr int kTrialsBelow = 2, kTrialsAbove = 3;
constexpr double kTrialRatio = 4.0;
// Where damping has grown this far past Marquardt's diagonal, the step is the gradient's
// direction at a length under the lattice: the model has nothing left to offer.
constexpr double kLargestDamping = 1e6;
// A level (a set of free coordinates on one model grid) is done when an iteration lowers
// the score by less than this share.
constexpr double kSmallestGain = 2e-3;
// A trial that moves no parameter by this share of its lattice step is no move.
constexpr double kSmallestMove = 0.1;

// The fewest rays a model cell should hold on average for its Jacobian to show a trend
// rather than noise (measured on the 36-height freeform: 1e5 rays on 90 x 45 cells, 25 a
// cell, and 1e6 on 360 x 180, 15 a cell, carry it to its floor; 1e5 on 360 x 180 do not).
constexpr double kRaysPerModelCell = 15.0;
// The first model's cells: as coarse as this, no coarser (a broad shape moves light by
// tens of degrees; from the flat start the 36-height freeform needs it: with 12 degree
// cells first it ended 2.4 x the floor for one seed of five, with 10 degree cells 1.0 x).
constexpr double kCoarsestModelCellDeg = 10.0;

// The grids the model's residual is taken on, coarse to fine, each made of blocks of the
// stage's cells: the coarsest whose cells span at most kCoarsestModelCellDeg, then the
// finest whose cells hold kRaysPerModelCell rays on average.
std::vector<std::pair<std::uint32_t, std::uint32_t>> model_grids(std::uint32_t w, std::uint32_t h,
                                                                 std::uint64_t rays) {
    std::pair<std::uint32_t, std::uint32_t> coarse{w, h}, fine{0, 0};
    for (std::uint32_t factor = 1; factor <= std::min(w, h); ++factor) {
        if (w % factor != 0 || h % factor != 0 || h / factor < 4) continue;
        const std::pair<std::uint32_t, std::uint32_t> grid{w / factor, h / factor};
        if (360.0 / double(grid.first) <= kCoarsestModelCellDeg) coarse = grid;
        if (fine.first == 0 &&
            double(rays) >= kRaysPerModelCell * double(grid.first) * double(grid.second))
            fine = grid;
    }
    // Where the rays hold no finer cells than the coarse model's, the ray-limited grid alone.
    if (fine.first == 0 ||
        std::uint64_t(fine.first) * fine.second <= std::uint64_t(coarse.first) * coarse.second)
        return {fine.first == 0 ? coarse : fine};
    return {coarse, fine};
}

// r = sqrt(w) (F - D) on the model grid (F and D on the stage's grid).
Eigen::VectorXd residual(const FarField& farfield, const FarField& desired, FarFieldMetric metric,
                         std::uint32_t w, std::uint32_t h) {
    const FarField a = farfield.width == w ? farfield : coarsen_farfield(farfield, w, h);
    const FarField d = desired.width == w ? desired : coarsen_farfield(desired, w, h);
    Eigen::VectorXd r(a.lm.size());
    for (std::size_t i = 0; i < a.lm.size(); ++i)
        r[Eigen::Index(i)] =
            (a.lm[i] - d.lm[i]) * std::sqrt(metric_cell_weight(metric, std::uint32_t(i / w), w, h));
    return r;
}

// One coordinate of the search: a direction in the parameters and the difference step
// along it. A mode's direction moves the grid's heights by 1 mm RMS per unit; a parameter
// of its own is its unit vector.
struct Direction {
    std::vector<double> unit;
    double step = 0.0; // the central difference's half-width, in the direction's units
    std::size_t degree = 0;
};

std::vector<Direction> directions(const SampleCoordinates& c, const ParameterSpace& space) {
    const std::size_t n = space.size();
    std::vector<Direction> out(n);
    // Whether coordinate k is a mode (its column is not the unit vector of parameter k).
    const auto is_mode = [&](std::size_t k) {
        if (c.transform.empty()) return false;
        for (std::size_t p = 0; p < n; ++p)
            if (c.transform[p * n + k] != (p == k ? 1.0 : 0.0)) return true;
        return false;
    };
    // A grid's lattice step: its heights' finest (the parameters the modes move).
    double grid_step = HUGE_VAL;
    for (std::size_t k = 0; k < n; ++k)
        if (is_mode(k))
            for (std::size_t p = 0; p < n; ++p)
                if (c.transform[p * n + k] != 0.0) grid_step = std::min(grid_step, space.step[p]);
    for (std::size_t k = 0; k < n; ++k) {
        Direction& d = out[k];
        d.degree = c.degree.empty() ? 0 : c.degree[k];
        d.unit.assign(n, 0.0);
        if (c.transform.empty()) {
            d.unit[k] = 1.0;
            d.step = 2.0 * space.step[k];
            continue;
        }
        double squares = 0.0;
        for (std::size_t p = 0; p < n; ++p)
            squares += c.transform[p * n + k] * c.transform[p * n + k];
        const bool mode = is_mode(k);
        // A mode's entries over the grid's heights: unit RMS there.
        const double norm = mode ? std::sqrt(squares / double(c.modes)) : std::sqrt(squares);
        for (std::size_t p = 0; p < n; ++p)
            d.unit[p] = c.transform[p * n + k] / norm;
        d.step = 2.0 * (mode ? grid_step : space.step[k]);
    }
    return out;
}

} // namespace

StopReason run_levenberg(Objective& f, const std::vector<double>& x0, LevenbergReport& report,
                         ModeOrder order) {
    const ParameterSpace& space = f.space();
    const std::size_t n = space.size();
    const Fidelity& fidelity = f.stage().fidelity;
    const FarField desired =
        f.desired().width == fidelity.farfield_w && f.desired().height == fidelity.farfield_h
            ? f.desired()
            : coarsen_farfield(f.desired(), fidelity.farfield_w, fidelity.farfield_h);
    const FarFieldMetric metric = f.scene().optimize.metric;
    const auto inside = [&](std::vector<double> x) {
        for (std::size_t k = 0; k < n; ++k)
            x[k] = std::clamp(x[k], space.lo[k], space.hi[k]);
        return x;
    };
    std::vector<double> x = inside(x0);
    const SampleCoordinates coordinates =
        sample_coordinates(f.scene().reflector, space, x, f.scene().optimize.height_sampling);
    const std::vector<Direction> along = directions(coordinates, space);
    // The degrees freed in turn (coarse to fine), or all of them at once.
    std::size_t finest = 0;
    for (const Direction& d : along)
        finest = std::max(finest, d.degree);
    std::vector<std::size_t> degrees;
    for (std::size_t g = order == ModeOrder::ByDegree ? std::min<std::size_t>(1, finest) : finest;
         g <= finest; ++g)
        degrees.push_back(g);
    report = {.modes = coordinates.modes};
    const auto moved = [&](const std::vector<double>& y) {
        for (std::size_t k = 0; k < n; ++k)
            if (std::abs(y[k] - x[k]) >= kSmallestMove * space.step[k]) return true;
        return false;
    };
    for (const std::size_t degree : degrees) {
        std::vector<std::size_t> free;
        for (std::size_t k = 0; k < n; ++k)
            if (along[k].degree <= degree) free.push_back(k);
        const auto m = Eigen::Index(free.size());
        report.degree = degree;
        for (const auto& [w, h] :
             model_grids(fidelity.farfield_w, fidelity.farfield_h, fidelity.rays)) {
            const std::string grid = fmt::format("{}x{}", w, h);
            if (std::find(report.model_grids.begin(), report.model_grids.end(), grid) ==
                report.model_grids.end())
                report.model_grids.push_back(grid);
            double lambda = 1e-2;
            // The model at x, kept while no step moves x (only the damping changes).
            std::vector<double> modelled_at;
            Eigen::MatrixXd normal;
            Eigen::VectorXd gradient;
            double score = 0.0;
            while (true) {
                if (modelled_at != x) {
                    // The Jacobian's points: each free coordinate's step either way, inside the
                    // box, traced with x as one list of batches.
                    std::vector<std::vector<double>> points{x};
                    for (const std::size_t k : free)
                        for (const double sign : {1.0, -1.0}) {
                            std::vector<double> y = x;
                            for (std::size_t p = 0; p < n; ++p)
                                y[p] += sign * along[k].step * along[k].unit[p];
                            points.push_back(inside(std::move(y)));
                        }
                    const Objective::ScoredFarFields traced = f.evaluate_all_with_farfields(points);
                    ++report.jacobians;
                    score = traced.scores[0];
                    // An infeasible x (a start that cuts the source) has no far field to model.
                    if (traced.farfields[0].lm.empty()) {
                        report.verdict = "stopped: the start is infeasible (no far field to model)";
                        return StopReason::Converged;
                    }
                    const Eigen::VectorXd r = residual(traced.farfields[0], desired, metric, w, h);
                    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(r.size(), m);
                    for (Eigen::Index j = 0; j < m; ++j) {
                        const std::size_t k = free[std::size_t(j)];
                        // How far the two points lie apart along the direction (a bound may
                        // have shortened either side); an infeasible side (no far field) is
                        // replaced by x, leaving the difference one-sided.
                        std::size_t up = 1 + 2 * std::size_t(j), down = up + 1;
                        if (traced.farfields[up].lm.empty()) up = 0;
                        if (traced.farfields[down].lm.empty()) down = 0;
                        double span = 0.0, units = 0.0;
                        for (std::size_t p = 0; p < n; ++p) {
                            span += (points[up][p] - points[down][p]) * along[k].unit[p];
                            units += along[k].unit[p] * along[k].unit[p];
                        }
                        span /= units;
                        if (!(std::abs(span) > 1e-12)) continue; // no room: its column stays 0
                        jacobian.col(j) =
                            (residual(traced.farfields[up], desired, metric, w, h) -
                             residual(traced.farfields[down], desired, metric, w, h)) /
                            span;
                    }
                    normal = jacobian.transpose() * jacobian;
                    gradient = jacobian.transpose() * r;
                    modelled_at = x;
                }
                // A coordinate that moves nothing has a zero row: a trace's worth of ridge
                // keeps the system solvable without moving it.
                const double ridge = 1e-12 * (1.0 + normal.diagonal().maxCoeff());
                // The trial steps, one per damping value, inside the box.
                std::vector<std::vector<double>> trials;
                std::vector<double> trial_lambda;
                std::set<std::vector<double>> seen;
                for (int t = -kTrialsBelow; t <= kTrialsAbove; ++t) {
                    const double l = lambda * std::pow(kTrialRatio, t);
                    Eigen::MatrixXd damped = normal;
                    for (Eigen::Index j = 0; j < m; ++j)
                        damped(j, j) = normal(j, j) * (1.0 + l) + ridge;
                    const Eigen::VectorXd step = damped.ldlt().solve(-gradient);
                    std::vector<double> y = x;
                    for (Eigen::Index j = 0; j < m; ++j)
                        if (std::isfinite(step[j]))
                            for (std::size_t p = 0; p < n; ++p)
                                y[p] += step[j] * along[free[std::size_t(j)]].unit[p];
                    y = inside(std::move(y));
                    if (moved(y) && seen.insert(y).second)
                        trials.push_back(y), trial_lambda.push_back(l);
                }
                ++report.iterations;
                if (trials.empty()) break; // every step under a tenth of the lattice's
                const std::vector<double> scores = f.evaluate_all(trials);
                const std::size_t best =
                    std::size_t(std::min_element(scores.begin(), scores.end()) - scores.begin());
                if (scores[best] < score) {
                    x = trials[best];
                    lambda = trial_lambda[best];
                    if (score - scores[best] < kSmallestGain * score) break;
                    continue;
                }
                // No trial improved: damp harder than any tried.
                lambda *= std::pow(kTrialRatio, kTrialsAbove + kTrialsBelow + 1);
                if (lambda > kLargestDamping) break;
            }
        }
    }
    report.verdict = fmt::format(
        "converged{}: no damped step on the {} far field gains {:.1f} % or moves a parameter a "
        "tenth of its step",
        coordinates.modes > 0 ? fmt::format(" with all {} modes free", coordinates.modes) : "",
        report.model_grids.empty() ? "stage's" : report.model_grids.back(), 100.0 * kSmallestGain);
    return StopReason::Converged;
}

} // namespace fird
