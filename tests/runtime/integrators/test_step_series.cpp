// Per-step series (integrators/step_series.hpp): exact mean and median while
// every value is listed, the mean exact and the median within 1 % beyond,
// memory that stops growing, the last value changed or taken back once,
// and a saved series given back whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "tensormass/integrators/step_series.hpp"

namespace tensormass {
namespace {

double exact_median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

/// Step times of a run: a lognormal spread around 2 ms.
std::vector<double> step_times(std::size_t count) {
  std::mt19937_64 rng(7);
  std::lognormal_distribution<double> time(std::log(2.0), 0.4);
  std::vector<double> values(count);
  for (double& x : values) x = time(rng);
  return values;
}

TEST(StepSeries, ListedValuesGiveTheExactMeanAndMedian) {
  const StepSeries<double> series{4.0, 1.0, 3.0, 10.0};
  EXPECT_EQ(series.size(), 4u);
  EXPECT_DOUBLE_EQ(series.mean(), 4.5);
  EXPECT_DOUBLE_EQ(series.median(), 3.5);
  EXPECT_DOUBLE_EQ(series.sum(), 18.0);
  EXPECT_EQ(series.listed(), (std::vector<double>{4.0, 1.0, 3.0, 10.0}));
  EXPECT_EQ(StepSeries<double>().median(), 0.0);
}

TEST(StepSeries, BeyondTheListTheMeanIsExactAndTheMedianWithinOnePercent) {
  const std::vector<double> values = step_times(200000);
  StepSeries<double> series;
  double sum = 0;
  for (double x : values) series.push_back(x), sum += x;
  EXPECT_EQ(series.size(), values.size());
  EXPECT_EQ(series.listed().size(), StepSeries<double>::kListed);
  EXPECT_TRUE(std::equal(series.listed().begin(), series.listed().end(), values.begin()));
  EXPECT_NEAR(series.mean(), sum / static_cast<double>(values.size()), 1e-12 * sum);
  const double median = exact_median(values);
  EXPECT_NEAR(series.median(), median, 0.01 * median);
}

TEST(StepSeries, MemoryStopsGrowingAfterTheListedSteps) {
  StepSeries<double> series;
  for (std::size_t i = 0; i < StepSeries<double>::kListed + 10; ++i) series.push_back(1.0);
  const auto after_list = series.saved();
  for (int i = 0; i < 100000; ++i) series.push_back(2.0);
  const auto later = series.saved();
  EXPECT_EQ(later.listed.size(), after_list.listed.size());
  EXPECT_EQ(later.bins.size(), after_list.bins.size());
  EXPECT_EQ(later.count, after_list.count + 100000);
}

TEST(StepSeries, TheLastValueIsChangedOrTakenBackOnce) {
  StepSeries<int> newton{3, 2};
  newton.set_back(newton.back() + 4);  // a load step's earlier solves added to it
  EXPECT_EQ(newton.listed(), (std::vector<int>{3, 6}));
  EXPECT_EQ(newton.sum(), 9.0);
  newton.pop_back();
  EXPECT_EQ(newton.listed(), (std::vector<int>{3}));
  EXPECT_EQ(newton.size(), 1u);
  EXPECT_THROW(newton.pop_back(), std::logic_error);  // once after each push
  newton.push_back(5);
  EXPECT_DOUBLE_EQ(newton.median(), 4.0);
}

TEST(StepSeries, TakingBackBeyondTheListKeepsTheMedianAndSum) {
  const std::vector<double> values = step_times(StepSeries<double>::kListed * 3);
  StepSeries<double> series, reference;
  for (double x : values) series.push_back(x), reference.push_back(x);
  series.push_back(1e6);  // an outlier, taken back
  series.pop_back();
  EXPECT_EQ(series.size(), reference.size());
  EXPECT_EQ(series.median(), reference.median());
  EXPECT_NEAR(series.sum(), reference.sum(), 1e-9 * reference.sum());
}

TEST(StepSeries, ASavedSeriesComesBackWholeAndAForgedOneIsRefused) {
  StepSeries<double> series;
  for (double x : step_times(StepSeries<double>::kListed + 50)) series.push_back(x);
  EXPECT_EQ(StepSeries<double>(series.saved()), series);
  auto forged = series.saved();
  forged.count += 1;  // a count the bins do not hold
  EXPECT_THROW(StepSeries<double>{std::move(forged)}, std::invalid_argument);
  auto short_list = series.saved();
  short_list.listed.pop_back();
  EXPECT_THROW(StepSeries<double>{std::move(short_list)}, std::invalid_argument);
}

}  // namespace
}  // namespace tensormass
