// The batch's Gauss-Markov segments (estimator/gauss_markov_segments.hpp): the transition factor,
// and how a chain's factors are rewritten onto one value of the process per segment.
#include "estimator/gauss_markov_segments.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/error.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

TEST(GaussMarkovTransition, WhitensTheProcessStep) {
  const GaussMarkovTransition t(0.5, 0.8);
  const double x = 0.3, next = 0.1;
  const double* ptrs[] = {&x, &next};
  double r = 0.0;
  ASSERT_TRUE(t.Evaluate(ptrs, &r, nullptr));
  EXPECT_NEAR(r, (0.1 - 0.8 * 0.3) / (0.5 * std::sqrt(1.0 - 0.64)), 1e-12);
  EXPECT_THROW(GaussMarkovTransition(0.0, 0.5), InputError);
  EXPECT_THROW(GaussMarkovTransition(0.5, 1.0), InputError);
  EXPECT_THROW(GaussMarkovTransition(0.5, -0.1), InputError);
}

TEST(GaussMarkovTransition, JacobianMatchesNumericDifferences) {
  const GaussMarkovTransition t(0.17, std::exp(-10.0 / 100.0));
  const auto check = testing::CheckJacobians(t, {{0.12}, {-0.05}}, {nullptr, nullptr}, 1e-6,
                                             "Gauss-Markov transition");
  EXPECT_LT(check.worst_relative_error, 1e-8);
}

// A scalar cost on the process alone, standing in for a fix's factor.
class OnTheProcess final : public ceres::SizedCostFunction<1, 1> {
 public:
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = parameters[0][0];
    if (jacobians != nullptr && jacobians[0] != nullptr) jacobians[0][0] = 1.0;
    return true;
  }
};

// 25 states one second apart, each with a factor on the process and one on a constant global:
// tau 50 s gives 5 s segments starting at states 0, 5, 10, 15, 20. The factors of the first
// four segments move to their own values, the newest keeps the live one, the other global is
// untouched, and a transition ties each segment to the one before with rho = exp(-5 / 50).
TEST(GaussMarkovSegments, GivesEachSegmentItsOwnValueTiedByTheProcess) {
  constexpr int kStates = 25;
  double live = 0.4, constant = 0.0;
  const OnTheProcess cost;
  std::vector<FactorRecord> on_process(kStates), on_constant(kStates);
  std::vector<ChainState> chain(kStates);
  std::vector<TimeNs> times;
  for (int k = 0; k < kStates; ++k) {
    on_process[k] = {&cost, nullptr, {&live}};
    on_constant[k] = {&cost, nullptr, {&constant}};
    chain[k].factors = {&on_process[k], &on_constant[k]};
    times.push_back(FromSeconds(100.0 + k));
  }
  std::vector<double*> globals{&constant, &live};
  const GaussMarkovSegments segments(times, {{&live, 0.5, 50.0}}, 32, &chain, &globals);
  ASSERT_EQ(segments.segments(), std::vector<int>{5});
  ASSERT_EQ(globals.size(), 6u);
  EXPECT_EQ(globals[0], &constant);
  EXPECT_EQ(globals[1], &live);
  for (int k = 0; k < kStates; ++k) {
    SCOPED_TRACE(k);
    const int segment = k / 5;
    double* const expected = segment == 4 ? &live : globals[2 + segment];
    EXPECT_EQ(*globals[2 + std::min(segment, 3)], 0.0);  // the process's mean
    EXPECT_EQ(chain[k].factors[0]->blocks, std::vector<double*>{expected});
    EXPECT_EQ(chain[k].factors[1], &on_constant[k]);  // untouched
    const bool starts_a_segment = k > 0 && k % 5 == 0;
    ASSERT_EQ(chain[k].factors.size(), starts_a_segment ? 3u : 2u);
    if (!starts_a_segment) continue;
    const FactorRecord& transition = *chain[k].factors[2];
    double* const previous = globals[2 + segment - 1];
    EXPECT_EQ(transition.blocks, (std::vector<double*>{previous, expected}));
    // Its residual at (1, 0): -rho / sqrt(q).
    const double one = 1.0, zero = 0.0;
    const double* ptrs[] = {&one, &zero};
    double r = 0.0;
    ASSERT_TRUE(transition.cost->Evaluate(ptrs, &r, nullptr));
    const double rho = std::exp(-0.1);
    EXPECT_NEAR(r, -rho / (0.5 * std::sqrt(1.0 - rho * rho)), 1e-12);
  }
  EXPECT_EQ(live, 0.4);  // the live value as it was
}

// A process the chain's factors do not use gets no segments; a chain shorter than one segment
// is left as it was; a long chain is cut into at most max_segments.
TEST(GaussMarkovSegments, LeavesUnusedAndShortProcessesAndCapsTheCount) {
  double used = 0.0, unused = 0.0;
  const OnTheProcess cost;
  constexpr int kStates = 400;  // 400 s
  std::vector<FactorRecord> records(kStates);
  std::vector<ChainState> chain(kStates);
  std::vector<TimeNs> times;
  for (int k = 0; k < kStates; ++k) {
    records[k] = {&cost, nullptr, {&used}};
    chain[k].factors = {&records[k]};
    times.push_back(FromSeconds(k));
  }
  std::vector<double*> globals{&used, &unused};
  {
    std::vector<ChainState> copy = chain;
    const GaussMarkovSegments s(times, {{&unused, 0.5, 100.0}}, 32, &copy, &globals);
    EXPECT_EQ(s.segments(), std::vector<int>{0});
    EXPECT_EQ(globals.size(), 2u);
  }
  {
    // The first 50 s against segments of tau / 10 = 100 s.
    std::vector<ChainState> first(chain.begin(), chain.begin() + 50);
    const std::vector<TimeNs> first_times(times.begin(), times.begin() + 50);
    const GaussMarkovSegments s(first_times, {{&used, 0.5, 1000.0}}, 32, &first, &globals);
    EXPECT_EQ(s.segments(), std::vector<int>{1});
    EXPECT_EQ(globals.size(), 2u);
    EXPECT_EQ(first[49].factors, std::vector<const FactorRecord*>{&records[49]});
  }
  {
    // 320 s in segments of exactly 320 / 32 = 10 s: the state at 320 s stays in the 32nd.
    std::vector<ChainState> first(chain.begin(), chain.begin() + 321);
    const std::vector<TimeNs> first_times(times.begin(), times.begin() + 321);
    const GaussMarkovSegments s(first_times, {{&used, 0.5, 100.0}}, 32, &first, &globals);
    EXPECT_EQ(s.segments(), std::vector<int>{32});
    globals.resize(2);
  }
  std::vector<ChainState> copy = chain;
  const GaussMarkovSegments s(times, {{&used, 0.5, 10.0}}, 32, &copy, &globals);
  // A tenth of tau would be 1 s (400 segments); 32 at most: 399 s / 32 = 12.47 s, so with a state
  // every whole second a segment starts every 13 s: 31 of them.
  EXPECT_EQ(s.segments(), std::vector<int>{31});
  EXPECT_EQ(globals.size(), 2u + 30u);
  EXPECT_DOUBLE_EQ(GaussMarkovSegments::SegmentLength(10.0, 399.0, 32), 399.0 / 32);
  EXPECT_DOUBLE_EQ(GaussMarkovSegments::SegmentLength(100.0, 60.0, 32), 10.0);
}

}  // namespace
}  // namespace statebench::est
