// Rounds of Ceres solves over the directions not held at a bound, with the Karush-Kuhn-Tucker
// check between them.
#include "bounded_solve.hpp"

#include <ceres/iteration_callback.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "slicecap/fit/argument_error.hpp"

namespace slicecap::fit::detail {
namespace {

// More rounds than a fit has directions to hold and let go: a direction that keeps landing on its
// bound and being let go again ends the solve with the last round's outcome.
constexpr int kMaximumRounds = 12;

// Each of the block's free directions a tangent coordinate: its coordinates all take that step.
class DirectionsManifold final : public ceres::Manifold {
 public:
  DirectionsManifold(int size, std::vector<const std::vector<int>*> directions)
      : size_(size), directions_(std::move(directions)) {}
  int AmbientSize() const override { return size_; }
  int TangentSize() const override { return static_cast<int>(directions_.size()); }
  bool Plus(const double* x, const double* delta, double* xPlusDelta) const override {
    for (int i = 0; i < size_; ++i) xPlusDelta[i] = x[i];
    for (std::size_t k = 0; k < directions_.size(); ++k)
      for (int i : *directions_[k]) xPlusDelta[i] += delta[k];
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    const int cols = TangentSize();
    for (int i = 0; i < size_ * cols; ++i) jacobian[i] = 0.0;
    for (int k = 0; k < cols; ++k)
      for (int i : *directions_[std::size_t(k)]) jacobian[i * cols + k] = 1.0;
    return true;
  }
  bool Minus(const double* y, const double* x, double* yMinusX) const override {
    for (std::size_t k = 0; k < directions_.size(); ++k) {
      double sum = 0.0;
      for (int i : *directions_[k]) sum += y[i] - x[i];
      yMinusX[k] = sum / static_cast<double>(directions_[k]->size());
    }
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    for (int i = 0; i < TangentSize() * size_; ++i) jacobian[i] = 0.0;
    for (std::size_t k = 0; k < directions_.size(); ++k)
      for (int i : *directions_[k])
        jacobian[k * std::size_t(size_) + std::size_t(i)] = 1.0 / double(directions_[k]->size());
    return true;
  }

 private:
  int size_;
  std::vector<const std::vector<int>*> directions_;
};

struct Direction {
  std::size_t block;
  const std::vector<int>* coordinates;
};

// -1 when every coordinate of `d` is at its lower bound, +1 at its upper, 0 otherwise.
int boundSide(const std::vector<BoundedBlock>& blocks, const Direction& d) {
  const BoundedBlock& b = blocks[d.block];
  bool lower = true, upper = true;
  for (int i : *d.coordinates) {
    const double value = b.values[i], slack = 1e-12 * (1.0 + std::abs(value));
    lower = lower && value <= b.lower[std::size_t(i)] + slack;
    upper = upper && value >= b.upper[std::size_t(i)] - slack;
  }
  return lower ? -1 : upper ? 1 : 0;
}

class Rounds {
 public:
  Rounds(const ceres::CostFunction& cost, std::vector<BoundedBlock>& blocks, double tolerance)
      : cost_(cost), blocks_(blocks), tolerance_(tolerance) {
    for (std::size_t b = 0; b < blocks.size(); ++b)
      for (const std::vector<int>& coordinates : blocks[b].moves)
        directions_.push_back({b, &coordinates});
  }

  const std::vector<Direction>& directions() const { return directions_; }

  // A start outside its box is moved onto it (Ceres would project it at its first iteration; a
  // block held whole never reaches Ceres).
  void projectIntoBounds() const {
    for (BoundedBlock& b : blocks_)
      for (int i = 0; i < b.size(); ++i)
        b.values[i] = std::clamp(b.values[i], b.lower[std::size_t(i)], b.upper[std::size_t(i)]);
  }

  // Which directions to hold at the current values: every one on a bound, but for the one whose
  // release the Gauss-Newton model likes best: its step (the free directions re-solved with it)
  // moves it inward and lowers the model by more than `tolerance` of the cost beyond what the free
  // directions alone would. One at a time, as an active-set method drops constraints: two let go
  // together may push each other back out.
  std::vector<bool> held() const {
    std::vector<bool> held(directions_.size(), false);
    std::vector<int> sides(directions_.size());
    std::vector<int> free, onBound;
    for (std::size_t k = 0; k < directions_.size(); ++k) {
      sides[k] = boundSide(blocks_, directions_[k]);
      held[k] = sides[k] != 0;
      (held[k] ? onBound : free).push_back(int(k));
    }
    if (onBound.empty()) return held;
    Eigen::MatrixXd a;
    Eigen::VectorXd r;
    if (!linearise(a, r)) return held;  // not finite here: hold, the solve will say
    const Eigen::VectorXd gradient = a.transpose() * r;
    const Eigen::MatrixXd normal = a.transpose() * a;
    const double freeDecrease = modelDecrease(gradient, normal, free, nullptr);
    const double threshold = tolerance_ * 0.5 * r.squaredNorm();
    double bestGain = threshold;
    int release = -1;
    for (int k : onBound) {
      std::vector<int> with = free;
      with.push_back(k);
      double stepK = 0.0;
      const double gain = modelDecrease(gradient, normal, with, &stepK) - freeDecrease;
      if (sides[std::size_t(k)] * stepK < 0.0 && gain > bestGain) {
        bestGain = gain;
        release = k;
      }
    }
    if (release >= 0) held[std::size_t(release)] = false;
    return held;
  }

  // The decrease of the Gauss-Newton model 1/2 |r + A d|^2 at its minimum over the directions
  // `over` (the others 0); `lastStep` receives the step of the last of them. The normal matrix is
  // scaled to a unit diagonal first, as Ceres scales its Jacobian, so that a direction whose
  // column is small beside the others' is not lost to the decomposition's rank threshold.
  static double modelDecrease(const Eigen::VectorXd& gradient, const Eigen::MatrixXd& normal,
                              const std::vector<int>& over, double* lastStep) {
    if (over.empty()) return 0.0;  // (Eigen's decompositions fail on an empty matrix)
    Eigen::VectorXd scale(Eigen::Index(over.size()));
    for (std::size_t k = 0; k < over.size(); ++k) {
      const double diagonal = normal(over[k], over[k]);
      scale(Eigen::Index(k)) = diagonal > 0.0 ? 1.0 / std::sqrt(diagonal) : 1.0;
    }
    const Eigen::VectorXd g = scale.cwiseProduct(gradient(over));
    const Eigen::MatrixXd n = scale.asDiagonal() * normal(over, over) * scale.asDiagonal();
    const Eigen::VectorXd step = -Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(n).solve(g);
    if (lastStep != nullptr) *lastStep = step(step.size() - 1);  // the scale is positive: same sign
    return -(g.dot(step) + 0.5 * step.dot(n * step));
  }

  // The residuals and their Jacobian over every direction at the current values.
  bool linearise(Eigen::MatrixXd& a, Eigen::VectorXd& r) const {
    std::vector<const double*> parameters;
    std::vector<Eigen::Index> firstColumn;
    Eigen::Index columns = 0;
    for (BoundedBlock& b : blocks_) {
      parameters.push_back(b.values);
      firstColumn.push_back(columns);
      columns += b.size();
    }
    Eigen::MatrixXd jacobian;
    if (!denseJacobian(cost_, parameters, r, jacobian) || !r.allFinite()) return false;
    a = Eigen::MatrixXd::Zero(r.size(), Eigen::Index(directions_.size()));
    for (std::size_t k = 0; k < directions_.size(); ++k)
      for (int i : *directions_[k].coordinates)
        a.col(Eigen::Index(k)) += jacobian.col(firstColumn[directions_[k].block] + i);
    return a.allFinite();
  }

  double costNow() const {
    std::vector<const double*> parameters;
    for (BoundedBlock& b : blocks_) parameters.push_back(b.values);
    std::vector<double> r(std::size_t(cost_.num_residuals()));
    if (!cost_.Evaluate(parameters.data(), r.data(), nullptr))
      return std::numeric_limits<double>::infinity();
    double sum = 0.0;
    for (double value : r) sum += value * value;
    return 0.5 * sum;
  }

  // A problem over the directions not `held`; false when nothing is free.
  bool build(ceres::Problem& problem, const std::vector<bool>& held) const {
    std::vector<double*> pointers;
    bool anyFree = false;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      BoundedBlock& block = blocks_[b];
      pointers.push_back(block.values);
      problem.AddParameterBlock(block.values, block.size());
      std::vector<const std::vector<int>*> free;
      bool eachAlone = true;
      for (std::size_t k = 0; k < directions_.size(); ++k)
        if (directions_[k].block == b && !held[k]) free.push_back(directions_[k].coordinates);
      for (std::size_t k = 0; k < free.size(); ++k)
        eachAlone = eachAlone && free[k]->size() == 1 && (*free[k])[0] == int(k);
      if (free.empty()) {
        problem.SetParameterBlockConstant(block.values);
      } else {
        anyFree = true;
        if (!(eachAlone && int(free.size()) == block.size()))
          problem.SetManifold(block.values, new DirectionsManifold(block.size(), std::move(free)));
        for (int i = 0; i < block.size(); ++i) {
          if (std::isfinite(block.lower[std::size_t(i)]))
            problem.SetParameterLowerBound(block.values, i, block.lower[std::size_t(i)]);
          if (std::isfinite(block.upper[std::size_t(i)]))
            problem.SetParameterUpperBound(block.values, i, block.upper[std::size_t(i)]);
        }
      }
    }
    // Ceres never modifies a cost function; it only takes a non-const pointer.
    problem.AddResidualBlock(const_cast<ceres::CostFunction*>(&cost_), nullptr, pointers);
    return anyFree;
  }

 private:
  const ceres::CostFunction& cost_;
  std::vector<BoundedBlock>& blocks_;
  double tolerance_;
  std::vector<Direction> directions_;
};

// Ends a solve when a free direction is on its bound after a step (it reached it, or the step
// was cut back there), so that the next round holds it instead of crawling along it. (A direction
// just let go can be cut back at the first step when the others are far from their solution; the
// next round holds it again, and the last round runs without this stop, so such a loop costs
// rounds, never the outcome.)
class StopAtBound final : public ceres::IterationCallback {
 public:
  StopAtBound(const std::vector<BoundedBlock>& blocks, const std::vector<Direction>& directions,
              const std::vector<bool>& held)
      : blocks_(blocks), directions_(directions), held_(held) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    radius_ = summary.trust_region_radius;
    if (summary.iteration == 0 || !summary.step_is_successful) return ceres::SOLVER_CONTINUE;
    for (std::size_t k = 0; k < directions_.size(); ++k)
      if (!held_[k] && boundSide(blocks_, directions_[k]) != 0) {
        landed_ = true;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    return ceres::SOLVER_CONTINUE;
  }
  bool landed() const { return landed_; }
  double radius() const { return radius_; }

 private:
  const std::vector<BoundedBlock>& blocks_;
  const std::vector<Direction>& directions_;
  const std::vector<bool>& held_;
  bool landed_ = false;
  double radius_ = 0.0;
};

}  // namespace

bool denseJacobian(const ceres::CostFunction& cost, const std::vector<const double*>& parameters,
                   Eigen::VectorXd& residuals, Eigen::MatrixXd& jacobian) {
  const Eigen::Index rows = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<std::vector<double>> perBlock;  // Ceres' layout: row-major, one array a block
  std::vector<double*> pointers;
  Eigen::Index columns = 0;
  for (const auto size : sizes) {
    perBlock.emplace_back(std::size_t(rows) * std::size_t(size));
    pointers.push_back(perBlock.back().data());
    columns += size;
  }
  residuals.resize(rows);
  if (!cost.Evaluate(parameters.data(), residuals.data(), pointers.data())) return false;
  jacobian.resize(rows, columns);
  Eigen::Index column = 0;
  for (std::size_t b = 0; b < perBlock.size(); ++b) {
    jacobian.middleCols(column, sizes[b]) =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            perBlock[b].data(), rows, sizes[b]);
    column += sizes[b];
  }
  return true;
}

BoundedBlock unboundedBlock(double* values, int size) {
  BoundedBlock block;
  block.values = values;
  block.lower.assign(std::size_t(size), -std::numeric_limits<double>::infinity());
  block.upper.assign(std::size_t(size), std::numeric_limits<double>::infinity());
  for (int i = 0; i < size; ++i) block.moves.push_back({i});
  return block;
}

BoundedSolveSummary solveHoldingBounds(const ceres::CostFunction& cost,
                                       std::vector<BoundedBlock>& blocks,
                                       ceres::Solver::Options options) {
  const auto& sizes = cost.parameter_block_sizes();
  if (sizes.size() != blocks.size())
    throw FitArgumentError("solveHoldingBounds: the cost has " + std::to_string(sizes.size()) +
                           " parameter blocks, " + std::to_string(blocks.size()) + " given");
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (blocks[b].size() != sizes[b] || blocks[b].upper.size() != blocks[b].lower.size() ||
        blocks[b].values == nullptr)
      throw FitArgumentError("solveHoldingBounds: block " + std::to_string(b) +
                             " does not match the cost's size " + std::to_string(sizes[b]));
  const Rounds rounds(cost, blocks, options.function_tolerance);
  const int iterationBudget = options.max_num_iterations;
  const double firstRadius = options.initial_trust_region_radius;
  options.update_state_every_iteration = true;
  // With bounds, Ceres' trust region follows every step with a projected Armijo line search
  // (Kanzow et al.). Kept: in a curved valley it turns a step the trust region would reject into
  // a shorter accepted one (a measured table's GGX solve, rgl satin_white, converged in 17
  // iterations with it and not in 200 without). Its default cubic interpolation evaluates the
  // Jacobian at the trial step, two more an iteration (a Ward table's fit 0.25 -> 0.57 s); the
  // quadratic one needs the cost alone there.
  options.line_search_interpolation_type = ceres::QUADRATIC;
  BoundedSolveSummary outcome;
  rounds.projectIntoBounds();
  std::vector<bool> held = rounds.held();
  while (true) {
    ceres::Problem::Options problemOptions;
    problemOptions.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problemOptions);
    if (!rounds.build(problem, held)) {
      // Nothing free: a solution if no direction is worth letting go.
      const std::vector<bool> next = rounds.held();
      if (next != held) {
        held = next;
        continue;
      }
      outcome.cost = rounds.costNow();
      outcome.converged = std::isfinite(outcome.cost);
      outcome.message = "every direction held at a bound";
      return outcome;
    }
    const int remaining = iterationBudget - outcome.iterations;
    if (remaining <= 0) {
      outcome.converged = false;
      outcome.message = "iteration limit reached after " + std::to_string(outcome.rounds) +
                        " rounds of holding parameters on their bounds";
      return outcome;
    }
    // The last round allowed runs as plain Ceres would (the step cut back at the bounds, no stop
    // when a direction reaches one): it may crawl, but it ends as Ceres' own solve would, not as
    // "not converged" for want of rounds.
    const bool lastRound = outcome.rounds + 1 >= kMaximumRounds;
    ceres::Solver::Options roundOptions = options;
    roundOptions.max_num_iterations = remaining;
    StopAtBound stop(blocks, rounds.directions(), held);
    if (!lastRound) roundOptions.callbacks.push_back(&stop);
    ceres::Solver::Summary summary;
    ceres::Solve(roundOptions, &problem, &summary);
    ++outcome.rounds;
    outcome.iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    outcome.cost = summary.final_cost;
    outcome.message = summary.message;
    outcome.converged =
        summary.termination_type == ceres::CONVERGENCE && std::isfinite(summary.final_cost);
    if (!stop.landed() && (!outcome.converged || lastRound)) return outcome;
    const std::vector<bool> next = rounds.held();
    if (!stop.landed() && next == held) return outcome;
    held = next;
    // The next round starts from the trust region this one reached, never below the first one's
    // (a region shrunk by rejected steps would make the next round's steps too small to count).
    options.initial_trust_region_radius = std::max(stop.radius(), firstRadius);
  }
}

}  // namespace slicecap::fit::detail
