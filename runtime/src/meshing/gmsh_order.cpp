// Second-order meshes by Gmsh (see gmsh_order.hpp): Gmsh reads and writes the
// files, the project's reader checks both sides.
#include "tensormass/meshing/gmsh_order.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "io/gmsh_session.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"

namespace tensormass {
namespace {

void check_first_order(const Mesh& mesh, const std::string& path) {
  for (const ElementBlock& block : mesh.blocks)
    if (block.element->order != 1)
      throw InputError("raise-order: " + path + " holds " + block.element->name +
                       " cells, of order 2 already: give a first-order mesh");
}

/// Gmsh's own message from whatever its API threw.
std::string gmsh_failure() {
  try {
    throw;
  } catch (const std::string& message) {
    return message;
  } catch (const char* message) {
    return message ? message : "unknown error";
  } catch (const std::exception& error) {
    return error.what();
  } catch (...) {
    return "unknown error";
  }
}

/// Gmsh opens `input`, raises it to order 2 and writes `path`.
void raise_in_gmsh(const RaiseOrderSpec& spec, const std::string& path) {
  const detail::GmshSession session;
  try {
    gmsh::open(spec.input);
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", spec.complete ? 0 : 1);
    gmsh::model::mesh::setOrder(2);
    gmsh::option::setNumber("Mesh.MshFileVersion", spec.format == io::MshFormat::v22 ? 2.2 : 4.1);
    gmsh::option::setNumber("Mesh.Binary", 0);
    gmsh::write(path);
  } catch (...) {
    throw InputError("raise-order: Gmsh failed on " + spec.input + ": " + gmsh_failure());
  }
}

}  // namespace

Mesh raise_order_with_gmsh(const RaiseOrderSpec& spec) {
  if (std::filesystem::path(spec.input).extension() != ".msh")
    throw InputError("raise-order: " + spec.input + " is not a Gmsh .msh file");
  if (std::filesystem::path(spec.output).extension() != ".msh")
    throw InputError("raise-order: the output " + spec.output + " must end in .msh");
  check_first_order(read_mesh(spec.input), spec.input);
  // Gmsh picks the format from the extension: the temporary keeps ".msh".
  const std::string temporary = spec.output + ".tmp-" + std::to_string(::getpid()) + ".msh";
  std::error_code ignored;
  try {
    raise_in_gmsh(spec, temporary);
  } catch (...) {
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  Mesh raised;
  try {
    raised = read_mesh(temporary);
  } catch (const InputError& error) {
    std::filesystem::remove(temporary, ignored);
    std::string message = error.what();
    if (message.rfind(temporary, 0) == 0) message = "Gmsh's result" + message.substr(temporary.size());
    throw InputError("raise-order: " + message +
                     (spec.complete ? " (without --complete Gmsh makes its serendipity elements)" : ""));
  }
  std::filesystem::rename(temporary, spec.output, ignored);
  if (ignored) {
    std::filesystem::remove(temporary, ignored);
    throw InputError("raise-order: cannot write " + spec.output);
  }
  raised.source = spec.output;
  return raised;
}

}  // namespace tensormass
