// scripts/results/render_*.py under /usr/bin/python3: the results pages
// written from their benchmark's JSON are what the scripts make of the
// committed JSON, so that a figure in a page cannot disagree with its
// measurement.
#include <gtest/gtest.h>

#include <string>

#include "script_test_support.hpp"

namespace {

using test_support::Result;

struct RenderedPage {
  const char* script;
  const char* inputs;  ///< under docs/results/
  const char* page;
};

class RenderedResultsPage : public ::testing::TestWithParam<RenderedPage> {};

TEST_P(RenderedResultsPage, IsWhatItsScriptMakesOfItsJson) {
  const RenderedPage& p = GetParam();
  std::string arguments;
  for (std::string rest = p.inputs; !rest.empty();) {
    const std::size_t space = rest.find(' ');
    arguments += " '" + test_support::source_path("docs/results/" + rest.substr(0, space)) + "'";
    rest = space == std::string::npos ? "" : rest.substr(space + 1);
  }
  const Result result = script_test::run_script(std::string("results/") + p.script, arguments);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, test_support::read_file(test_support::source_path(std::string("docs/results/") + p.page)))
      << "regenerate it: /usr/bin/python3 scripts/results/" << p.script << " ... > docs/results/" << p.page;
}

INSTANTIATE_TEST_SUITE_P(
    Pages, RenderedResultsPage,
    ::testing::Values(RenderedPage{"render_refine.py", "refine.json", "refine.md"},
                      RenderedPage{"render_paper.py", "paper.json", "paper.md"},
                      RenderedPage{"render_kernels.py", "kernels.json kernels_avx2.json", "kernels.md"},
                      RenderedPage{"render_locking.py", "locking.json", "locking.md"},
                      RenderedPage{"render_cooks_membrane.py", "cooks_membrane.json", "cooks_membrane.md"},
                      RenderedPage{"render_thick_cylinder.py", "thick_cylinder.json", "thick_cylinder.md"},
                      RenderedPage{"render_soak.py", "soak_steps.json soak_thorax.json", "soak.md"},
                      RenderedPage{"render_python.py", "python_stepping.json", "python.md"},
                      RenderedPage{"render_runtime.py", "runtime.json", "runtime.md"},
                      RenderedPage{"render_linear_solvers.py", "linear_solvers.json", "linear_solvers.md"},
                      RenderedPage{"render_scaling.py", "scaling.json", "scaling.md"},
                      RenderedPage{"render_mpi.py", "mpi_agreement.json mpi_scaling.json", "mpi.md"},
                      RenderedPage{"render_adaptive.py", "adaptive_bench.json adaptive_needle_fine.json",
                                   "adaptive.md"}),
    [](const auto& info) {
      std::string name = info.param.page;
      return name.substr(0, name.find('.'));
    });

}  // namespace
