// An error is sent as its kind (one byte) and its message, from the rank
// that met it to every rank, which throws it again.
#include "tensormass/parallel/rank_errors.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::parallel {

namespace {

enum Kind : char { kNone, kInputError, kNumericalError, kOutputError, kOtherError };

/// Runs work; the kind and message of what it threw (kNone: nothing) as bytes.
std::vector<char> run_catching(const std::function<void()>& work) {
  const auto bytes = [](Kind kind, const char* what) {
    const std::string text = std::string(1, kind) + what;
    return std::vector<char>(text.begin(), text.end());
  };
  try {
    work();
  } catch (const InputError& e) {
    return bytes(kInputError, e.what());
  } catch (const NumericalError& e) {
    return bytes(kNumericalError, e.what());
  } catch (const OutputError& e) {  // exit 4 on any number of ranks
    return bytes(kOutputError, e.what());
  } catch (const std::exception& e) {
    return bytes(kOtherError, e.what());
  }
  return {kNone};
}

void throw_again(const std::vector<char>& error) {
  const std::string message(error.begin() + 1, error.end());
  if (error.front() == kInputError) throw InputError(message);
  if (error.front() == kNumericalError) throw NumericalError(message);
  if (error.front() == kOutputError) throw OutputError(message);
  throw std::runtime_error(message);
}

}  // namespace

void on_root(const std::function<void()>& work) {
  if (world_size() == 1) return work();
  std::vector<char> error = world_rank() == 0 ? run_catching(work) : std::vector<char>{};
  broadcast_bytes_from_root(error);
  if (error.front() != kNone) throw_again(error);
}

void on_every_rank(const std::function<void()>& work) {
  if (world_size() == 1) return work();
  std::vector<char> error = run_catching(work);
  const RankedValue first = min_over_ranks(error.front() == kNone ? world_size() : world_rank());
  if (first.value == world_size()) return;
  broadcast_bytes_from(first.rank, error);
  throw_again(error);
}

}  // namespace tensormass::parallel
