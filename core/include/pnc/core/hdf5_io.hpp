#pragma once
// pnc/core/hdf5_io.hpp: the few HDF5 operations pnc's file formats need, with errors that
// name the file and the dataset. Uses the serial HDF5 C++ API; never include this header in
// a translation unit that also includes deal.II (two HDF5 flavours would meet).
//
// Conventions of every pnc HDF5 file (docs/formats.md "Conventions", D237): physical quantities are
// double, counts, indices, step numbers and versions are 64-bit signed integers (the integral
// overloads below choose that by the argument's type), matrices are row-major 2-D datasets,
// every dataset that carries a physical quantity has a string attribute `units`, and every file
// carries the `/provenance` group of write_provenance(). Readers of numbers (read_scalar,
// read_vector, attr_double) accept either type, so files of earlier versions stay readable.
#include <Eigen/Dense>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace pnc::h5 {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

class File {
public:
  enum class Mode { read, truncate };
  File(const std::string& path, Mode mode);
  ~File();
  File(File&&) noexcept;
  File& operator=(File&&) noexcept;
  const std::string& path() const;

  // --- writing (paths like "/constants/C11"; parent groups are created) ---
  void write_scalar(const std::string& dataset, double value);
  void write_matrix(const std::string& dataset, const RowMatrix& m);
  void write_vector(const std::string& dataset, const std::vector<double>& v);
  void write_string(const std::string& dataset, const std::string& text);
  void set_attr(const std::string& object, const std::string& name, const std::string& value);
  void set_attr(const std::string& object, const std::string& name, double value);
  /// Integers (counts, steps, ids, versions) as 64-bit signed integer datasets/attributes.
  void write_integer(const std::string& dataset, std::int64_t value);
  void write_integers(const std::string& dataset, const std::vector<std::int64_t>& v);
  void set_attr_integer(const std::string& object, const std::string& name, std::int64_t value);
  /// Any integral argument (int, std::size_t, long, bool) is written as an integer.
  template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
  void write_scalar(const std::string& dataset, T value) {
    write_integer(dataset, static_cast<std::int64_t>(value));
  }
  template <class T, std::enable_if_t<std::is_integral_v<T>, int> = 0>
  void set_attr(const std::string& object, const std::string& name, T value) {
    set_attr_integer(object, name, static_cast<std::int64_t>(value));
  }

  // --- reading; throw pnc::InputError naming file and dataset ---
  bool exists(const std::string& object) const;
  double read_scalar(const std::string& dataset) const;
  RowMatrix read_matrix(const std::string& dataset) const;
  std::vector<double> read_vector(const std::string& dataset) const;
  std::string read_string(const std::string& dataset) const;
  /// A scalar stored as an integer; a floating-point dataset is an InputError ("expected an
  /// integer dataset").
  std::int64_t read_integer(const std::string& dataset) const;
  /// True when `object` is a dataset of an integer type.
  bool is_integer(const std::string& dataset) const;
  std::optional<std::string> attr_string(const std::string& object, const std::string& name) const;
  std::optional<double> attr_double(const std::string& object, const std::string& name) const;
  std::vector<std::string> children(const std::string& group) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The provenance block every pnc HDF5 file carries (docs/formats.md "Conventions"):
/// `/provenance/software` (text: pnc version and git hash), attributes of `/provenance`:
/// `created` (UTC, ISO 8601), `command` (`command`, or when empty the command line of the
/// running pnc program, pnc::invocation(); "(not run from the pnc command)" when there is none,
/// e.g. a solver linking the library), and the root attribute `software` (same text).
void write_provenance(File& f, const std::string& command = "");

} // namespace pnc::h5
