// SPDX-License-Identifier: GPL-3.0-or-later
#include "bridge/WeibullMle.hpp"

#include "bridge/VoxelGrid.hpp" // failSetting

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace armour {
namespace bridge {

double weibullCdf(double d, double shape, double scale) {
  if (d <= 0.0) return 0.0;
  if (scale <= 0.0) return 1.0;
  return -std::expm1(-std::pow(d / scale, shape));
}

namespace {

struct Prepared {
  std::vector<double> logE; ///< ln(d / dMax)
  std::vector<double> w;    ///< weights
  double dMax = 0.0;        ///< unit: that of the samples
  double total = 0.0;       ///< total weight
  double meanLog = 0.0;     ///< sum w ln e / W
};

/// The profile-likelihood condition g(k) and its derivative (see the header).
void profile(const Prepared& s, double k, double& g, double& dg) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  for (std::size_t i = 0; i < s.logE.size(); ++i) {
    const double l = s.logE[i];
    const double ek = s.w[i] * std::exp(k * l); // w e^k, e <= 1: no overflow
    s0 += ek;
    s1 += ek * l;
    s2 += ek * l * l;
  }
  // s0 >= the weight of the maximum sample (e = 1) > 0.
  const double m1 = s1 / s0;
  g = 1.0 / k + s.meanLog - m1;
  dg = -1.0 / (k * k) - (s2 / s0 - m1 * m1);
}

} // namespace

storm::WeibullFit fitWeibull(const std::vector<double>& values, const std::vector<double>& weights) {
  if (!weights.empty() && weights.size() != values.size()) {
    std::ostringstream m;
    m << values.size() << " values but " << weights.size() << " weights: give one weight per value or none";
    failSetting("fitWeibull", m.str());
  }
  Prepared s;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w >= 0.0) || !std::isfinite(w)) {
      std::ostringstream m;
      m << "weight[" << i << "] = " << w << ": weights must be finite and >= 0";
      failSetting("fitWeibull", m.str());
    }
    if (w == 0.0) continue;
    if (!(values[i] > 0.0) || !std::isfinite(values[i])) {
      std::ostringstream m;
      m << "value[" << i << "] = " << values[i] << ": Weibull samples must be positive and finite (count zero deviations apart)";
      failSetting("fitWeibull", m.str());
    }
    s.dMax = std::max(s.dMax, values[i]);
    s.total += w;
  }
  storm::WeibullFit fit;
  if (s.total <= 0.0) {
    fit.shape = 1.0;
    fit.scale = 0.0;
    fit.ksStatistic = -1.0;
    fit.samples = 0;
    return fit;
  }
  std::vector<double> kept, keptW;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w == 0.0) continue;
    s.logE.push_back(std::log(values[i] / s.dMax));
    s.w.push_back(w);
    s.meanLog += w * s.logE.back();
    kept.push_back(values[i]);
    keptW.push_back(w);
  }
  s.meanLog /= s.total;

  // Bracket the root of the decreasing g in [kMin, kMax].
  double lo = kMinWeibullShape, hi = kMaxWeibullShape;
  double g = 0.0, dg = 0.0;
  double k = 0.0;
  profile(s, hi, g, dg);
  if (g >= 0.0) {
    k = hi; // (nearly) all samples equal: the likelihood still grows at the cap
  } else {
    profile(s, lo, g, dg);
    if (g <= 0.0) {
      k = lo;
    } else {
      // Start from the moment estimate: the standard deviation of ln d is pi / (k sqrt 6).
      double var = 0.0;
      for (std::size_t i = 0; i < s.logE.size(); ++i) var += s.w[i] * (s.logE[i] - s.meanLog) * (s.logE[i] - s.meanLog);
      var /= s.total;
      k = var > 0.0 ? 1.2825498301618641 / std::sqrt(var) : 1.0;
      if (!(k > lo && k < hi)) k = std::sqrt(lo * hi);
      for (int it = 0; it < 200; ++it) {
        profile(s, k, g, dg);
        if (g > 0.0) lo = k; else hi = k;
        double next = k - g / dg;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi); // Newton left the bracket: bisect
        const bool done = std::fabs(next - k) <= 1e-13 * k || hi - lo <= 1e-13 * k;
        k = next;
        if (done) break;
      }
    }
  }
  double s0 = 0.0;
  for (std::size_t i = 0; i < s.logE.size(); ++i) s0 += s.w[i] * std::exp(k * s.logE[i]);
  fit.shape = k;
  fit.scale = s.dMax * std::pow(s0 / s.total, 1.0 / k);
  fit.samples = static_cast<std::int64_t>(std::llround(s.total));
  fit.ksStatistic = ksStatistic(kept, keptW, fit.shape, fit.scale);
  return fit;
}

double ksStatistic(const std::vector<double>& values, const std::vector<double>& weights, double shape, double scale) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&values](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  double total = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) total += weights.empty() ? 1.0 : weights[i];
  if (total <= 0.0) return -1.0;
  double d = 0.0, cum = 0.0;
  std::size_t i = 0;
  while (i < order.size()) {
    // Samples of equal value form one jump of the empirical CDF.
    const double v = values[order[i]];
    double jump = 0.0;
    while (i < order.size() && values[order[i]] == v) {
      jump += weights.empty() ? 1.0 : weights[order[i]];
      ++i;
    }
    const double f = weibullCdf(v, shape, scale);
    d = std::max(d, std::fabs(f - cum / total));
    cum += jump;
    d = std::max(d, std::fabs(f - cum / total));
  }
  return d;
}

} // namespace bridge
} // namespace armour
