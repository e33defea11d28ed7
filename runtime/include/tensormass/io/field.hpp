/// \file field.hpp
/// A named data array over points or cells, as the output formats write it
/// (vtk_writer.hpp) and the adaptive model and checkpoints hand it over.
#ifndef TENSORMASS_IO_FIELD_HPP
#define TENSORMASS_IO_FIELD_HPP

#include <string>
#include <vector>

namespace tensormass::io {

/// One data array: `components` values per point (or per cell), flattened.
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;  ///< count by components
};

}  // namespace tensormass::io

#endif
