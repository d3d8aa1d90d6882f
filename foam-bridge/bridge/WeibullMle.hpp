// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WeibullMle.hpp
/// Maximum-likelihood fit of a two-parameter Weibull distribution F(d) = 1 - exp(-(d/lambda)^k)
/// to positive, optionally weighted, samples, with the Kolmogorov-Smirnov statistic of the fit.
/// The variability model of seed 000 (section 2.2) is four such fits (docs/foam-bridge.md).
///
/// Method (docs/foam-bridge.md, "Weibull fit"): for weights w_i and samples d_i the log-likelihood
/// is sum w_i [ln k - k ln lambda + (k - 1) ln d_i - (d_i / lambda)^k]. Setting its lambda
/// derivative to zero gives lambda^k = sum w d^k / W (closed form), and the profile likelihood in
/// k has the stationarity condition
///     g(k) = 1/k + sum w ln d / W - sum w d^k ln d / sum w d^k = 0,
/// with g strictly decreasing (g' = -1/k^2 - a weighted variance of ln d), so the root is unique;
/// it is found by Newton's method safeguarded by bisection. Samples are divided by their maximum
/// first (g does not change) so d^k neither overflows nor loses the largest samples.
///
/// Degenerate inputs give documented results, never NaN:
///  - no samples (total weight 0): shape 1, scale 0 ("no variability"), ks -1, samples 0;
///  - all samples equal (one sample included): the likelihood grows without bound as k grows (a
///    step distribution); the shape is capped at kMaxWeibullShape and the scale is the common value.
///
/// Plain C++11 (shared with the OpenFOAM function object).

#include "storm/StormFile.hpp"

#include <cstddef>
#include <vector>

namespace armour {
namespace bridge {

/// Largest shape returned (unit: -): a Weibull of shape 100 is within 1 % of its scale with
/// probability 0.63 (a step for any practical purpose); it stands for "all deviations equal".
constexpr double kMaxWeibullShape = 100.0;
/// Smallest shape searched (unit: -): below it the distribution spans hundreds of decades.
constexpr double kMinWeibullShape = 1e-3;

/// Weibull CDF 1 - exp(-(d/scale)^shape); 0 for d <= 0; a step at 0 if scale == 0.
double weibullCdf(double d, double shape, double scale);

/// Fit by maximum likelihood. `values` must be positive and finite (zeros have no logarithm: the
/// caller counts them apart, see DeviationHistogram); `weights` (>= 0) has the same length or is
/// empty for weight 1 each. `samples` of the result is the total weight rounded to an integer.
/// Throws std::invalid_argument for a non-positive value or a negative weight.
storm::WeibullFit fitWeibull(const std::vector<double>& values, const std::vector<double>& weights = std::vector<double>());

/// Kolmogorov-Smirnov statistic D = sup |F_empirical - F| of weighted samples against a Weibull;
/// -1 if the total weight is 0.
double ksStatistic(const std::vector<double>& values, const std::vector<double>& weights, double shape, double scale);

} // namespace bridge
} // namespace armour
