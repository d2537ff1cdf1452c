#include "core/psychophysics/fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "core/math/random.h"
#include "core/psychophysics/observer.h"

namespace enact::psychophysics {
namespace {

constexpr int kParams = 3;
using Point = std::array<double, kParams>;

// the search coordinates: the threshold (its log for a Weibull), then those fitted of the
// log spread and the lapse's angle u (lapse = max_lapse sin^2 u, so 0 and max are reached)
int free_coordinates(const FitSettings& s) { return 1 + (s.spread > 0.0 ? 0 : 1) + (s.free_lapse ? 1 : 0); }

// the coordinates of a function: (threshold, log spread, lapse angle) packed as above
Point pack(double threshold_coordinate, double log_spread, double lapse_angle, const FitSettings& s) {
  Point p{threshold_coordinate, 0.0, 0.0};
  std::size_t i = 1;
  if (s.spread <= 0.0) p[i++] = log_spread;
  if (s.free_lapse) p[i] = lapse_angle;
  return p;
}

// the function at a threshold coordinate and the other free coordinates
PsychometricFunction function_at(double threshold_coordinate, const double* rest, const FitSettings& s) {
  PsychometricFunction f;
  f.shape = s.shape;
  f.guess = s.guess;
  f.threshold = s.shape == Shape::weibull ? std::exp(threshold_coordinate) : threshold_coordinate;
  std::size_t i = 0;
  f.spread = s.spread > 0.0 ? s.spread : std::exp(rest[i++]);
  const double u = std::sin(rest[i]);
  f.lapse = s.free_lapse ? s.max_lapse * u * u : s.lapse;
  return f;
}
PsychometricFunction function_at(const Point& p, const FitSettings& s) { return function_at(p[0], p.data() + 1, s); }

// Nelder-Mead (Nelder & Mead 1965; reflection 1, expansion 2, contraction and shrink 0.5)
// minimising `cost` over the first `dims` coordinates, from `start` with initial steps `step`
template <class Cost>
Point nelder_mead(Cost&& cost, Point start, const Point& step, int dims) {
  std::vector<Point> simplex(static_cast<std::size_t>(dims + 1), start);
  for (int i = 0; i < dims; ++i) simplex[static_cast<std::size_t>(i + 1)][static_cast<std::size_t>(i)] += step[static_cast<std::size_t>(i)];
  std::vector<double> value(simplex.size());
  for (std::size_t i = 0; i < simplex.size(); ++i) value[i] = cost(simplex[i]);
  auto along = [&](const Point& from, const Point& to, double t) {
    Point p = from;
    for (int i = 0; i < dims; ++i) p[static_cast<std::size_t>(i)] = from[static_cast<std::size_t>(i)] + t * (to[static_cast<std::size_t>(i)] - from[static_cast<std::size_t>(i)]);
    return p;
  };
  for (int iteration = 0; iteration < 20000; ++iteration) {
    // order: best first
    std::vector<std::size_t> idx(simplex.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return value[a] < value[b]; });
    std::vector<Point> ordered;
    std::vector<double> ordered_value;
    for (std::size_t i : idx) {
      ordered.push_back(simplex[i]);
      ordered_value.push_back(value[i]);
    }
    simplex = ordered;
    value = ordered_value;
    // converged: the values and the points agree to rounding
    double size = 0.0;
    for (std::size_t i = 1; i < simplex.size(); ++i) {
      for (int d = 0; d < dims; ++d) size = std::max(size, std::abs(simplex[i][static_cast<std::size_t>(d)] - simplex[0][static_cast<std::size_t>(d)]));
    }
    if (value.back() - value.front() < 1e-13 * (1.0 + std::abs(value.front())) && size < 1e-10) break;
    // the centroid of all but the worst
    Point centroid{};
    for (std::size_t i = 0; i + 1 < simplex.size(); ++i) {
      for (int d = 0; d < dims; ++d) centroid[static_cast<std::size_t>(d)] += simplex[i][static_cast<std::size_t>(d)] / dims;
    }
    for (int d = dims; d < kParams; ++d) centroid[static_cast<std::size_t>(d)] = start[static_cast<std::size_t>(d)];
    const Point reflected = along(centroid, simplex.back(), -1.0);
    const double fr = cost(reflected);
    if (fr < value.front()) {
      const Point expanded = along(centroid, simplex.back(), -2.0);
      const double fe = cost(expanded);
      simplex.back() = fe < fr ? expanded : reflected;
      value.back() = std::min(fe, fr);
    } else if (fr < value[value.size() - 2]) {
      simplex.back() = reflected;
      value.back() = fr;
    } else {
      const bool outside = fr < value.back();
      const Point contracted = along(centroid, outside ? reflected : simplex.back(), 0.5);
      const double fc = cost(contracted);
      if (fc < std::min(fr, value.back())) {
        simplex.back() = contracted;
        value.back() = fc;
      } else {
        for (std::size_t i = 1; i < simplex.size(); ++i) {
          simplex[i] = along(simplex[0], simplex[i], 0.5);
          value[i] = cost(simplex[i]);
        }
      }
    }
  }
  return simplex[static_cast<std::size_t>(std::min_element(value.begin(), value.end()) - value.begin())];
}

}  // namespace

std::vector<LevelCount> tally(const std::vector<Response>& responses) {
  std::map<double, LevelCount> by_level;
  for (const Response& r : responses) {
    LevelCount& c = by_level[r.level];
    c.level = r.level;
    c.trials += 1;
    c.correct += r.correct ? 1 : 0;
  }
  std::vector<LevelCount> out;
  for (const auto& [level, count] : by_level) out.push_back(count);
  return out;
}

double log_likelihood(const PsychometricFunction& f, const std::vector<LevelCount>& data) {
  double sum = 0.0;
  for (const LevelCount& c : data) {
    const double p = std::clamp(f.probability(c.level), 1e-300, 1.0 - 1e-16);
    sum += c.correct * std::log(p) + (c.trials - c.correct) * std::log1p(-p);
  }
  return sum;
}

Fit fit_ml(const std::vector<LevelCount>& data, const FitSettings& settings) {
  if (data.empty()) throw std::invalid_argument("no trials to fit");
  const bool weibull = settings.shape == Shape::weibull;
  if (weibull && data.front().level <= 0.0) throw std::invalid_argument("a Weibull needs levels > 0");
  const double low = data.front().level, high = data.back().level;
  const double range = high > low ? high - low : std::max(std::abs(high), 1.0);
  auto cost = [&](const Point& p) { return -log_likelihood(function_at(p, settings), data); };
  // start at the best of a coarse grid (the likelihood can have several local optima)
  Point best{};
  double best_cost = INFINITY;
  for (int i = 0; i <= 8; ++i) {
    for (int j = 0; j <= 4; ++j) {
      const double t = weibull ? std::log(low) + (std::log(high) - std::log(low)) * i / 8.0 : low + range * i / 8.0;
      const double spread = weibull ? std::log(1.0 + 1.0 * j) : std::log(range / 16.0 * std::pow(2.0, j));
      const Point p = pack(weibull && high == low ? std::log(low) : t, spread, std::asin(std::sqrt(0.5 * std::min(0.02, settings.max_lapse) / settings.max_lapse)), settings);
      const double c = cost(p);
      if (c < best_cost) {
        best_cost = c;
        best = p;
      }
    }
  }
  // restarted until a restart no longer improves the optimum
  const int dims = free_coordinates(settings);
  const Point step = pack(weibull ? 0.2 : range / 8.0, 0.3, 0.3, settings);
  for (int restart = 0; restart < 10; ++restart) {
    const Point p = nelder_mead(cost, best, step, dims);
    const double c = cost(p);
    const bool moved = c < best_cost - 1e-12;
    best = p;
    best_cost = std::min(best_cost, c);
    if (!moved && restart > 0) break;
  }
  return {function_at(best, settings), -best_cost};
}

Interval profile_threshold(const std::vector<LevelCount>& data, const FitSettings& settings, const Fit& fit, double confidence) {
  const bool weibull = settings.shape == Shape::weibull;
  const double t_hat = fit.function.threshold;
  const double cut = fit.log_likelihood - 0.5 * std::pow(normal_quantile(0.5 + confidence / 2.0), 2.0);
  // the best log-likelihood with the threshold held at t (coordinates: log spread, lapse)
  const int dims = free_coordinates(settings) - 1;
  const double lapse_angle = std::asin(std::sqrt(settings.free_lapse ? fit.function.lapse / settings.max_lapse : 0.0));
  auto profile = [&](double t) {
    const double t_coordinate = weibull ? std::log(t) : t;
    auto cost = [&](const Point& p) { return -log_likelihood(function_at(t_coordinate, p.data(), settings), data); };
    if (dims == 0) return -cost({});
    // from the fit's own spread and a shallower one: the profile's optimum may be either
    double best = INFINITY;
    for (double widen : {0.0, 1.5}) {
      const Point full = pack(0.0, std::log(fit.function.spread) + widen, lapse_angle, settings);
      const Point start{full[1], full[2], 0.0};
      best = std::min(best, cost(nelder_mead(cost, nelder_mead(cost, start, {0.3, 0.3, 0.0}, dims), {0.1, 0.1, 0.0}, dims)));
    }
    return -best;
  };
  // each end: step out (geometrically towards 0 for a Weibull) until below the cut, then bisect
  const double span = std::max(data.back().level - data.front().level, t_hat);
  const double inf = std::numeric_limits<double>::infinity();
  auto end = [&](double direction) {
    double inside = t_hat, step = 0.05 * span;
    for (int i = 0; i < 40; ++i) {
      double t = inside + direction * step;
      if (weibull && t <= 0.0) t = 0.5 * inside;
      if (profile(t) < cut) {
        double a = inside, b = t;
        for (int k = 0; k < 40 && std::abs(b - a) > 1e-6 * t_hat; ++k) {
          const double mid = 0.5 * (a + b);
          (profile(mid) < cut ? b : a) = mid;
        }
        return 0.5 * (a + b);
      }
      inside = t;
      step *= 1.6;
    }
    return direction > 0 ? inf : (weibull ? 0.0 : -inf);
  };
  return {end(-1.0), end(+1.0)};
}

Resample resample_levels(const std::vector<LevelCount>& data) {
  return [data](const PsychometricFunction& f, std::uint64_t seed) {
    math::Random r(seed);
    std::vector<LevelCount> sample = data;
    for (LevelCount& c : sample) {
      const double p = f.probability(c.level);
      c.correct = 0;
      for (int i = 0; i < c.trials; ++i) c.correct += r.uniform() < p ? 1 : 0;
    }
    return sample;
  };
}

Resample resample_procedure(std::function<std::unique_ptr<Procedure>()> make) {
  return [make](const PsychometricFunction& f, std::uint64_t seed) {
    const VirtualObserver observer{f, seed};
    std::unique_ptr<Procedure> p = make();
    while (!p->finished()) p->tell(observer.correct(p->history().size(), p->next_level()));
    return tally(p->history());
  };
}

Interval bootstrap_threshold(const Resample& resample, const FitSettings& settings, const Fit& fit, int replicates, std::uint64_t seed,
                             double confidence) {
  std::vector<double> thresholds;
  for (int b = 0; b < replicates; ++b) {
    thresholds.push_back(fit_ml(resample(fit.function, math::derive_seed(seed, static_cast<std::uint64_t>(b))), settings).function.threshold);
  }
  std::sort(thresholds.begin(), thresholds.end());
  // percentiles by linear interpolation between order statistics
  auto percentile = [&](double q) {
    const double at = q * static_cast<double>(thresholds.size() - 1);
    const std::size_t i = static_cast<std::size_t>(at);
    const double frac = at - static_cast<double>(i);
    return i + 1 < thresholds.size() ? thresholds[i] * (1.0 - frac) + thresholds[i + 1] * frac : thresholds[i];
  };
  const double tail = (1.0 - confidence) / 2.0;
  return {percentile(tail), percentile(1.0 - tail)};
}

}  // namespace enact::psychophysics
