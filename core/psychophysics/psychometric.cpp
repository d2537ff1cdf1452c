#include "core/psychophysics/psychometric.h"

#include <cmath>

namespace enact::psychophysics {

const char* to_string(Shape shape) { return shape == Shape::gaussian ? "gaussian" : "weibull"; }

std::optional<Shape> shape_named(const std::string& name) {
  if (name == "gaussian") return Shape::gaussian;
  if (name == "weibull") return Shape::weibull;
  return std::nullopt;
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normal_quantile(double p) {
  // Acklam's rational start, then two Newton steps on erfc (to full double precision)
  const double q = p < 0.5 ? p : 1.0 - p;
  const double t = std::sqrt(-2.0 * std::log(q));
  double z = -(t - (2.515517 + 0.802853 * t + 0.010328 * t * t) / (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t));
  for (int i = 0; i < 3; ++i) z -= (normal_cdf(z) - q) / (std::exp(-0.5 * z * z) / std::sqrt(2.0 * M_PI));
  return p < 0.5 ? z : -z;
}

double PsychometricFunction::core(double x) const {
  if (shape == Shape::gaussian) return normal_cdf((x - threshold) / spread);
  if (x <= 0.0) return 0.0;
  // (x / scale)^spread with scale = threshold / ln2^(1/spread)
  return 1.0 - std::exp(-std::log(2.0) * std::pow(x / threshold, spread));
}

double PsychometricFunction::probability(double x) const { return guess + (1.0 - guess - lapse) * core(x); }

double PsychometricFunction::level_at(double p) const {
  const double f = (p - guess) / (1.0 - guess - lapse);
  if (shape == Shape::gaussian) return threshold + spread * normal_quantile(f);
  return threshold * std::pow(-std::log1p(-f) / std::log(2.0), 1.0 / spread);
}

}  // namespace enact::psychophysics
