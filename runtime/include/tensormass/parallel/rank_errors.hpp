/// \file rank_errors.hpp
/// Errors met by some MPI ranks, thrown on all of them: work that may fail
/// on one rank is followed by collective steps, and a rank that left with
/// an exception would leave the others waiting in them.
#ifndef TENSORMASS_PARALLEL_RANK_ERRORS_HPP
#define TENSORMASS_PARALLEL_RANK_ERRORS_HPP

#include <functional>

namespace tensormass::parallel {

/// Runs `work` on rank 0 alone; an exception it throws is thrown on every
/// rank with the same message (InputError, NumericalError and OutputError
/// keep their type, so the exit code is the same on any number of ranks;
/// others, NotPositiveDefiniteError's subtype too, become their base or
/// std::runtime_error), so that no rank waits for what
/// rank 0 will not send. On one rank, work().
void on_root(const std::function<void()>& work);

/// Runs `work` on every rank (collective); when it throws on some, every
/// rank throws the error of the lowest of them, as on_root does. On one
/// rank, work().
void on_every_rank(const std::function<void()>& work);

}  // namespace tensormass::parallel

#endif
