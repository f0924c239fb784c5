#pragma once
// The 1€ filter (Casiez, Roussel, Vogel, CHI 2012): a first-order low-pass filter whose cutoff
// rises with the filtered speed, so a still fingertip is smoothed hard (no jitter) and a fast
// one follows with little lag.

#include <array>

namespace sculpt::rt {

/// Tuning of a One-Euro filter. Frequencies in Hz.
struct OneEuroParams {
  /// Cutoff at rest: lower removes more jitter, at the cost of lag when moving slowly.
  double min_cutoff = 1.0;
  /// How fast the cutoff rises with speed (per unit of the signal per second): higher cuts lag.
  double beta = 0.0;
  /// Cutoff of the low-pass filter on the derivative.
  double d_cutoff = 1.0;

  /// @throw std::invalid_argument when a cutoff is not finite and > 0, or beta not finite and >= 0.
  void validate() const;
};

/// One scalar channel. filter() is noexcept and allocation-free; construction validates.
///
/// Rate rule: the sampling rate is 1 / (t - t_previous) whenever the timestamp increases. A
/// timestamp that does not increase (equal, earlier, or not finite) keeps the last rate, so the
/// output stays finite; the filter still takes that timestamp as the latest (as the reference
/// implementation does), so a source whose clock restarted recovers at its next sample.
/// Until two increasing timestamps have been seen, `nominal_rate_hz` is used.
class OneEuroFilter {
 public:
  /// @param nominal_rate_hz the rate assumed before timestamps give one (> 0).
  /// @throw std::invalid_argument for invalid parameters or rate.
  OneEuroFilter(const OneEuroParams& params, double nominal_rate_hz);

  /// Filters one sample taken at `timestamp_s` (seconds, any origin). The first sample after
  /// construction or reset() passes through unchanged. A non-finite `value` is ignored: the
  /// last output is returned and the state is left as it was (NaN would otherwise stick).
  double filter(double value, double timestamp_s) noexcept;

  /// Forgets every sample: the next one passes through. Parameters and nominal rate stay.
  void reset() noexcept;

  /// True once a sample has been taken since construction or reset().
  bool has_output() const noexcept { return has_output_; }
  /// The last output (0 before any sample).
  double last_output() const noexcept { return x_hat_; }
  /// The rate the last sample was filtered with, in Hz.
  double rate_hz() const noexcept { return rate_hz_; }
  const OneEuroParams& params() const noexcept { return params_; }

 private:
  OneEuroParams params_;
  double nominal_rate_hz_;
  double rate_hz_;
  bool has_output_ = false;
  bool has_time_ = false;
  double last_time_ = 0.0;
  double x_hat_ = 0.0;   // filtered value
  double dx_hat_ = 0.0;  // filtered derivative
};

/// A point: three independent One-Euro filters with the same parameters and timestamps.
class OneEuroFilter3 {
 public:
  /// @throw std::invalid_argument as OneEuroFilter.
  OneEuroFilter3(const OneEuroParams& params, double nominal_rate_hz);

  /// Filters a point. A point with any non-finite coordinate is ignored as a whole (the last
  /// output is returned), so the three channels never drift out of step.
  std::array<double, 3> filter(const std::array<double, 3>& point, double timestamp_s) noexcept;
  void reset() noexcept;
  bool has_output() const noexcept { return axes_[0].has_output(); }
  std::array<double, 3> last_output() const noexcept;

 private:
  std::array<OneEuroFilter, 3> axes_;
};

}  // namespace sculpt::rt
