/// \file step_series.hpp
/// A value per finished step (its wall time, its Newton iterations) in
/// memory that stops growing: the first kListed values are kept as they
/// are, and of all of them the count, the sum and a histogram of 1 %-wide
/// logarithmic bins, so that a run of millions of steps holds a few tens of
/// kilobytes. The mean is exact; the median is exact up to kListed values
/// and within 1 % beyond. The last value can be changed or taken back once
/// (a static load step solved again).
#ifndef TENSORMASS_INTEGRATORS_STEP_SERIES_HPP
#define TENSORMASS_INTEGRATORS_STEP_SERIES_HPP

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <utility>
#include <vector>

namespace tensormass {

template <class T>
class StepSeries {
 public:
  /// Values kept as they are (the per-step lists of summary.json).
  static constexpr std::size_t kListed = 1000;
  /// The histogram: bin k holds values in [kLowest 1.01^k, kLowest 1.01^(k+1)),
  /// values below kLowest (and zeros) in bin 0.
  static constexpr double kLowest = 1e-6, kRatio = 1.01;
  static constexpr int kBins = 3000;  // up to 1e-6 * 1.01^3000 = 9.6e6

  StepSeries() = default;
  StepSeries(std::initializer_list<T> values) {
    for (T value : values) push_back(value);
  }

  void push_back(T value) {
    if (count_ < kListed) listed_.push_back(value);
    ++count_;
    sum_ += static_cast<double>(value);
    add_to_bin(value, true);
    last_ = value;
    can_take_back_ = true;
  }
  std::size_t size() const { return count_; }
  /// The i-th listed value (i < listed().size()).
  T operator[](std::size_t i) const { return listed_.at(i); }
  void clear() { *this = StepSeries(); }
  bool empty() const { return count_ == 0; }
  T back() const { return last_; }
  /// The last value becomes `value` (a load step's earlier solves added to it).
  void set_back(T value) {
    take_back();
    push_back(value);
  }
  /// Takes the last value back; once after each push_back.
  void pop_back() { take_back(); }

  double sum() const { return sum_; }
  /// The first min(size(), kListed) values, in order.
  const std::vector<T>& listed() const { return listed_; }
  /// Exact while every value is listed (the mean summed as x / n, as it
  /// always was); sum / count beyond.
  double mean() const {
    if (count_ == 0) return 0.0;
    if (count_ > kListed) return sum_ / static_cast<double>(count_);
    double mean = 0;
    for (T x : listed_) mean += static_cast<double>(x) / static_cast<double>(count_);
    return mean;
  }
  /// Exact while every value is listed; beyond, the geometric centre of the
  /// histogram bin of the middle value (within 1 %).
  double median() const {
    if (count_ == 0) return 0.0;
    if (count_ <= kListed) {
      std::vector<T> sorted = listed_;
      std::sort(sorted.begin(), sorted.end());
      const std::size_t n = sorted.size();
      return n % 2 ? static_cast<double>(sorted[n / 2])
                   : (static_cast<double>(sorted[n / 2 - 1]) + static_cast<double>(sorted[n / 2])) / 2;
    }
    const std::uint64_t middle = (count_ + 1) / 2;  // 1-based rank
    std::uint64_t seen = 0;
    for (int bin = 0; bin < kBins; ++bin) {
      seen += bins_.empty() ? 0 : bins_[static_cast<std::size_t>(bin)];
      if (seen >= middle) return bin == 0 ? 0.0 : kLowest * std::pow(kRatio, bin + 0.5);
    }
    return kLowest * std::pow(kRatio, kBins);
  }

  /// What a checkpoint saves and gives back (saved() and StepSeries(saved)
  /// round-trip every value, bin and the last value).
  struct Saved {
    std::vector<T> listed;
    std::uint64_t count = 0;
    double sum = 0;
    std::vector<std::uint64_t> bins;  ///< kBins counts, or none when empty
    T last{};
    bool can_take_back = false;
  };
  Saved saved() const { return {listed_, count_, sum_, bins_, last_, can_take_back_}; }
  bool operator==(const StepSeries& other) const {
    return listed_ == other.listed_ && count_ == other.count_ && sum_ == other.sum_ && bins_ == other.bins_ &&
           last_ == other.last_ && can_take_back_ == other.can_take_back_;
  }
  /// std::invalid_argument when the parts do not fit each other.
  explicit StepSeries(Saved saved)
      : listed_(std::move(saved.listed)),
        count_(saved.count),
        sum_(saved.sum),
        bins_(std::move(saved.bins)),
        last_(saved.last),
        can_take_back_(saved.can_take_back) {
    std::uint64_t binned = 0;
    for (std::uint64_t n : bins_) binned += n;
    if (listed_.size() != std::min<std::uint64_t>(count_, kListed) ||
        !(bins_.empty() ? count_ == 0 : bins_.size() == kBins && binned == count_) || !std::isfinite(sum_) ||
        (can_take_back_ && count_ == 0))
      throw std::invalid_argument("a step series whose counts do not fit");
  }

 private:
  static int bin_of(T value) {
    const double x = static_cast<double>(value);
    if (!(x >= kLowest)) return 0;  // zeros, negatives and NaN too
    const int bin = static_cast<int>(std::log(x / kLowest) / std::log(kRatio));
    return std::clamp(bin, 0, kBins - 1);
  }
  void add_to_bin(T value, bool add) {
    if (bins_.empty()) bins_.assign(kBins, 0);
    std::uint64_t& bin = bins_[static_cast<std::size_t>(bin_of(value))];
    add ? ++bin : --bin;
  }
  void take_back() {
    if (!can_take_back_) throw std::logic_error("StepSeries: no last value to take back");
    if (count_ <= kListed) listed_.pop_back();
    --count_;
    sum_ -= static_cast<double>(last_);
    add_to_bin(last_, false);
    if (count_ == 0) sum_ = 0, bins_.clear();
    can_take_back_ = false;
  }

  std::vector<T> listed_;
  std::uint64_t count_ = 0;
  double sum_ = 0;
  std::vector<std::uint64_t> bins_;
  T last_{};
  bool can_take_back_ = false;
};

}  // namespace tensormass

#endif
