#pragma once
// Psychometric functions of a two-interval discrimination: the probability of a correct
// answer at a stimulus difference x (in the compared parameter's unit, e.g. N/m),
//   psi(x) = guess + (1 - guess - lapse) * F(x),
// with F a cumulative Gaussian or a Weibull (Wichmann & Hill 2001, "The psychometric
// function: I. Fitting, sampling and goodness of fit", P&P 63(8)). Both are parametrised by
// the threshold, the x where F = 0.5 (75 % correct in 2AFC without lapses): this is the JND
// enact reports, and JND / reference is the Weber fraction. A virtual observer answers with
// such a function (core/psychophysics/observer.h); the fits estimate one (fit.h).
#include <cstdint>
#include <optional>
#include <string>

namespace enact::psychophysics {

enum class Shape : std::uint8_t {
  gaussian,  // F(x) = Phi((x - threshold) / spread): spread is the sd, in x's unit
  weibull,   // F(x) = 1 - exp(-(x / scale)^spread), scale set so F(threshold) = 0.5; x > 0
};
const char* to_string(Shape shape);
std::optional<Shape> shape_named(const std::string& name);

struct PsychometricFunction {
  Shape shape = Shape::gaussian;
  double threshold = 1.0;  // x at F = 0.5: the JND
  double spread = 1.0;     // gaussian: sd (x's unit); weibull: the exponent (no unit)
  double guess = 0.5;      // the chance rate (0.5 for two intervals)
  double lapse = 0.0;      // the rate of answers given without regard to the stimulus

  // F(x) in [0, 1]
  double core(double x) const;
  // psi(x) = guess + (1 - guess - lapse) F(x)
  double probability(double x) const;
  // the x where psi(x) = p, for p strictly between guess and 1 - lapse
  double level_at(double p) const;
};

// the standard normal cumulative distribution and its inverse
double normal_cdf(double z);
double normal_quantile(double p);

}  // namespace enact::psychophysics
