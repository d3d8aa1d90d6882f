// SPDX-License-Identifier: GPL-3.0-or-later
// The Weibull maximum-likelihood fit (bridge/WeibullMle) and the histogram path the sampler uses
// (bridge/DeviationHistogram): recovery of known shape and scale from synthetic samples, the
// goodness of fit, and the degenerate inputs.

#include "bridge/DeviationHistogram.hpp"
#include "bridge/WeibullMle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

using namespace armour::bridge;

namespace {

/// n samples of Weibull(shape, scale) by inversion of the CDF (fixed seed: reproducible).
std::vector<double> weibullSamples(double shape, double scale, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> d(static_cast<std::size_t>(n));
  for (double& x : d) x = scale * std::pow(-std::log1p(-uniform(rng)), 1.0 / shape);
  return d;
}

struct Case {
  double shape;
  double scale;
};

} // namespace

// The issue asks for shape and scale within 3 % from 1e4 samples. The MLE's standard errors at
// n = 1e4 are 0.78 % (shape) and 1.05 % / k (scale), so 3 % is 2.9 sigma or more for k >= 1: a
// correct fit passes for any seed with probability > 99 %, and an estimator biased by more than a
// few percent fails.
TEST(WeibullMle, RecoversShapeAndScaleFrom1e4Samples) {
  const Case cases[] = {{1.0, 1.0}, {1.5, 0.2}, {2.0, 3.5}, {3.0, 0.05}, {0.7, 1.0}};
  unsigned seed = 11;
  for (const Case& c : cases) {
    const std::vector<double> d = weibullSamples(c.shape, c.scale, 10000, seed++);
    const armour::storm::WeibullFit fit = fitWeibull(d);
    // k = 0.7: the scale's standard error is 1.5 %; 3 % is 2 sigma, still asked of the fit.
    EXPECT_NEAR(fit.shape / c.shape, 1.0, 0.03) << "shape " << c.shape << " scale " << c.scale;
    EXPECT_NEAR(fit.scale / c.scale, 1.0, 0.03) << "shape " << c.shape << " scale " << c.scale;
    EXPECT_EQ(fit.samples, 10000);
    // Kolmogorov-Smirnov 1 % critical value for n = 1e4: 1.63 / sqrt(n) = 0.0163 (a fitted model
    // makes D smaller still).
    EXPECT_GT(fit.ksStatistic, 0.0);
    EXPECT_LT(fit.ksStatistic, 0.0163);
  }
}

// The fit must be the maximum of the likelihood, not just close to the truth: perturbing the shape
// or the scale by 1 % lowers the log-likelihood.
TEST(WeibullMle, IsTheLikelihoodMaximum) {
  const std::vector<double> d = weibullSamples(1.7, 0.8, 5000, 3);
  const armour::storm::WeibullFit fit = fitWeibull(d);
  auto logLikelihood = [&d](double k, double l) {
    double s = 0.0;
    for (double x : d) s += std::log(k / l) + (k - 1.0) * std::log(x / l) - std::pow(x / l, k);
    return s;
  };
  const double best = logLikelihood(fit.shape, fit.scale);
  for (double f : {0.99, 1.01}) {
    EXPECT_LT(logLikelihood(fit.shape * f, fit.scale), best);
    EXPECT_LT(logLikelihood(fit.shape, fit.scale * f), best);
  }
}

// A wrong model must show in the KS statistic (the test of the goodness-of-fit is able to fail).
TEST(WeibullMle, KsStatisticDetectsAWrongModel) {
  const std::vector<double> d = weibullSamples(2.0, 1.0, 10000, 5);
  EXPECT_LT(ksStatistic(d, {}, 2.0, 1.0), 0.0163);
  EXPECT_GT(ksStatistic(d, {}, 1.3, 1.0), 0.05);
  EXPECT_GT(ksStatistic(d, {}, 2.0, 1.3), 0.05);
}

// Integer weights are the same as repeated samples.
TEST(WeibullMle, WeightsEqualRepetition) {
  const std::vector<double> base = weibullSamples(1.2, 2.0, 300, 9);
  std::vector<double> repeated, weights;
  for (double x : base) {
    repeated.insert(repeated.end(), {x, x, x});
    weights.push_back(3.0);
  }
  const armour::storm::WeibullFit a = fitWeibull(repeated);
  const armour::storm::WeibullFit b = fitWeibull(base, weights);
  EXPECT_NEAR(a.shape, b.shape, 1e-9 * a.shape);
  EXPECT_NEAR(a.scale, b.scale, 1e-9 * a.scale);
  EXPECT_NEAR(a.ksStatistic, b.ksStatistic, 1e-12);
  EXPECT_EQ(a.samples, b.samples);
}

// The sampler's path: deviations in Pa binned 200 per decade, fitted after division by P_n. The
// binning moves ln d by at most 0.58 %: the binned fit must agree with the raw fit to 0.5 % and
// still recover the truth to 3 %.
TEST(DeviationHistogram, BinnedFitMatchesRawFit) {
  const double pn = 1025.0 * 9.81 * 3.25; // rho g a_n of seed 000's regular wave (H = 6.5 m), Pa
  const Case truth[4] = {{1.2, 0.08}, {1.6, 0.05}, {0.9, 0.03}, {2.2, 0.06}};
  DeviationHistogram h;
  std::vector<double> raw[4];
  for (int c = 0; c < 4; ++c) {
    raw[c] = weibullSamples(truth[c].shape, truth[c].scale, 10000, 100u + static_cast<unsigned>(c));
    const bool crest = c < 2;
    const bool above = c % 2 == 0;
    for (double d : raw[c]) h.add(crest, (above ? 1.0 : -1.0) * d * pn);
  }
  h.add(true, 0.0); // a zero deviation: counted apart, not fitted
  const armour::storm::Variability v = h.fit(pn, 3.25, "test");
  ASSERT_TRUE(v.present);
  EXPECT_EQ(h.zeroCount(true), 1.0);
  for (int c = 0; c < 4; ++c) {
    const armour::storm::WeibullFit rawFit = fitWeibull(raw[c]);
    const armour::storm::WeibullFit& binned = v.classes[static_cast<std::size_t>(c)];
    EXPECT_EQ(binned.samples, 10000) << c;
    EXPECT_NEAR(binned.shape / rawFit.shape, 1.0, 0.005) << c;
    EXPECT_NEAR(binned.scale / rawFit.scale, 1.0, 0.005) << c;
    EXPECT_NEAR(binned.shape / truth[c].shape, 1.0, 0.03 + (truth[c].shape < 1.0 ? 0.01 : 0.0)) << c;
    EXPECT_NEAR(binned.scale / truth[c].scale, 1.0, 0.03 + (truth[c].shape < 1.0 ? 0.01 : 0.0)) << c;
    // The binned KS statistic differs from the raw one by at most the largest bin mass.
    EXPECT_NEAR(binned.ksStatistic, rawFit.ksStatistic, 0.01) << c;
  }
  EXPECT_DOUBLE_EQ(v.probabilityAbove[0], 0.5);
  EXPECT_DOUBLE_EQ(v.normalisationPressure, pn);
}

TEST(DeviationHistogram, ProbabilityAboveCountsSigns) {
  DeviationHistogram h;
  for (int i = 0; i < 30; ++i) h.add(false, 10.0 + i);
  for (int i = 0; i < 10; ++i) h.add(false, -5.0 - i);
  for (int i = 0; i < 5; ++i) h.add(true, -1.0 - i);
  const armour::storm::Variability v = h.fit(1000.0, 0.1, "test");
  EXPECT_DOUBLE_EQ(v.probabilityAbove[1], 0.75);
  EXPECT_DOUBLE_EQ(v.probabilityAbove[0], 0.0);
  EXPECT_EQ(v.classes[0].samples, 0); // crest above: nothing
  EXPECT_EQ(v.classes[0].scale, 0.0);
}

TEST(DeviationHistogram, MergeAddsCounts) {
  DeviationHistogram a, b;
  a.add(true, 3.0);
  b.add(true, 3.0);
  b.add(false, -1e9); // beyond the last bin: kept in it, and counted as overflow
  a.merge(b);
  EXPECT_EQ(a.classCount(0), 2.0);
  EXPECT_EQ(a.classCount(3), 1.0);
  EXPECT_EQ(a.overflowCount(), 1.0);
}

// Degenerate data: documented results, never NaN.
TEST(WeibullMle, NoSamplesMeansNoVariability) {
  const armour::storm::WeibullFit fit = fitWeibull({});
  EXPECT_EQ(fit.shape, 1.0);
  EXPECT_EQ(fit.scale, 0.0);
  EXPECT_LT(fit.ksStatistic, 0.0);
  EXPECT_EQ(fit.samples, 0);
  const armour::storm::WeibullFit zeroWeights = fitWeibull({1.0, 2.0}, {0.0, 0.0});
  EXPECT_EQ(zeroWeights.scale, 0.0);
}

TEST(WeibullMle, OneSampleOrEqualSamplesGiveAStep) {
  for (const std::vector<double>& d : {std::vector<double>{0.3}, std::vector<double>(50, 0.3)}) {
    const armour::storm::WeibullFit fit = fitWeibull(d);
    EXPECT_EQ(fit.shape, kMaxWeibullShape);
    EXPECT_NEAR(fit.scale, 0.3, 1e-12);
    EXPECT_TRUE(std::isfinite(fit.ksStatistic));
    EXPECT_EQ(fit.samples, static_cast<std::int64_t>(d.size()));
  }
}

TEST(WeibullMle, AllZeroDeviationsGiveNoVariability) {
  DeviationHistogram h;
  for (int i = 0; i < 100; ++i) h.add(i % 2 == 0, 0.0);
  const armour::storm::Variability v = h.fit(1000.0, 0.1, "test");
  for (const armour::storm::WeibullFit& f : v.classes) {
    EXPECT_EQ(f.scale, 0.0);
    EXPECT_EQ(f.shape, 1.0);
    EXPECT_EQ(f.samples, 0);
  }
  EXPECT_EQ(h.zeroCount(true) + h.zeroCount(false), 100.0);
  EXPECT_DOUBLE_EQ(v.probabilityAbove[0], 0.5);
}

TEST(WeibullMle, RefusesNonPositiveSamples) {
  EXPECT_THROW(fitWeibull({1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(fitWeibull({1.0, -2.0}), std::invalid_argument);
  EXPECT_THROW(fitWeibull({1.0, 2.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(fitWeibull({1.0}, {-1.0}), std::invalid_argument);
}
