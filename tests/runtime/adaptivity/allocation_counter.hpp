// Counts every global allocation of the adaptivity tests (operator new is
// replaced in allocation_counter.cpp), so that a test can show that a loop
// makes none.
#ifndef TENSORMASS_TEST_ALLOCATION_COUNTER_HPP
#define TENSORMASS_TEST_ALLOCATION_COUNTER_HPP

#include <atomic>

namespace test_support {

extern std::atomic<long> allocation_count;

}  // namespace test_support

#endif
