#include "sculpt/rt/one_euro_filter.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sculpt/base/number_text.hpp"

namespace sculpt::rt {
namespace {

// Smoothing factor of a first-order low-pass filter with cutoff `cutoff_hz` sampled at
// `rate_hz`: alpha = 1 / (1 + tau / te), tau = 1 / (2 pi fc), te = 1 / rate.
double smoothing_factor(double cutoff_hz, double rate_hz) noexcept {
  const double tau = 1.0 / (2.0 * std::numbers::pi * cutoff_hz);
  const double te = 1.0 / rate_hz;
  return 1.0 / (1.0 + tau / te);
}

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void OneEuroParams::validate() const {
  if (!positive_finite(min_cutoff)) {
    throw std::invalid_argument("one-euro filter: min_cutoff must be finite and > 0 Hz, got " +
                                base::number_text(min_cutoff));
  }
  if (!positive_finite(d_cutoff)) {
    throw std::invalid_argument("one-euro filter: d_cutoff must be finite and > 0 Hz, got " +
                                base::number_text(d_cutoff));
  }
  if (!std::isfinite(beta) || beta < 0.0) {
    throw std::invalid_argument("one-euro filter: beta must be finite and >= 0, got " + base::number_text(beta));
  }
}

OneEuroFilter::OneEuroFilter(const OneEuroParams& params, double nominal_rate_hz)
    : params_(params), nominal_rate_hz_(nominal_rate_hz), rate_hz_(nominal_rate_hz) {
  params_.validate();
  if (!positive_finite(nominal_rate_hz)) {
    throw std::invalid_argument("one-euro filter: the nominal rate must be finite and > 0 Hz, got " +
                                base::number_text(nominal_rate_hz));
  }
}

double OneEuroFilter::filter(double value, double timestamp_s) noexcept {
  if (!std::isfinite(value)) return x_hat_;
  if (std::isfinite(timestamp_s)) {
    if (has_time_ && timestamp_s > last_time_) {
      const double rate = 1.0 / (timestamp_s - last_time_);
      // A gap below ~1e-308 s would give an infinite rate; keep the last one instead.
      if (std::isfinite(rate)) rate_hz_ = rate;
    }
    last_time_ = timestamp_s;
    has_time_ = true;
  }
  if (!has_output_) {
    has_output_ = true;
    x_hat_ = value;
    dx_hat_ = 0.0;
    return x_hat_;
  }
  // The derivative is taken against the previous *filtered* value, as in the paper's algorithm
  // and the reference implementation that produced the published test vector.
  const double dx = (value - x_hat_) * rate_hz_;
  dx_hat_ += smoothing_factor(params_.d_cutoff, rate_hz_) * (dx - dx_hat_);
  const double cutoff = params_.min_cutoff + params_.beta * std::abs(dx_hat_);
  x_hat_ += smoothing_factor(cutoff, rate_hz_) * (value - x_hat_);
  return x_hat_;
}

void OneEuroFilter::reset() noexcept {
  rate_hz_ = nominal_rate_hz_;
  has_output_ = false;
  has_time_ = false;
  last_time_ = 0.0;
  x_hat_ = 0.0;
  dx_hat_ = 0.0;
}

OneEuroFilter3::OneEuroFilter3(const OneEuroParams& params, double nominal_rate_hz)
    : axes_{OneEuroFilter(params, nominal_rate_hz), OneEuroFilter(params, nominal_rate_hz),
            OneEuroFilter(params, nominal_rate_hz)} {}

std::array<double, 3> OneEuroFilter3::filter(const std::array<double, 3>& point, double timestamp_s) noexcept {
  if (!std::isfinite(point[0]) || !std::isfinite(point[1]) || !std::isfinite(point[2])) {
    return last_output();
  }
  return {axes_[0].filter(point[0], timestamp_s), axes_[1].filter(point[1], timestamp_s),
          axes_[2].filter(point[2], timestamp_s)};
}

void OneEuroFilter3::reset() noexcept {
  for (OneEuroFilter& f : axes_) f.reset();
}

std::array<double, 3> OneEuroFilter3::last_output() const noexcept {
  return {axes_[0].last_output(), axes_[1].last_output(), axes_[2].last_output()};
}

}  // namespace sculpt::rt
