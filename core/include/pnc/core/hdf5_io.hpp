#pragma once
// pnc/core/hdf5_io.hpp: the few HDF5 operations pnc's file formats need, with errors that
// name the file and the dataset. Uses the serial HDF5 C++ API; never include this header in
// a translation unit that also includes deal.II (two HDF5 flavours would meet).
//
// Conventions of every pnc HDF5 file: numbers are double, matrices are row-major 2-D
// datasets, every dataset that carries a physical quantity has a string attribute `units`.
#include <Eigen/Dense>

#include <memory>
#include <optional>
#include <string>
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

  // --- reading; throw pnc::InputError naming file and dataset ---
  bool exists(const std::string& object) const;
  double read_scalar(const std::string& dataset) const;
  RowMatrix read_matrix(const std::string& dataset) const;
  std::vector<double> read_vector(const std::string& dataset) const;
  std::string read_string(const std::string& dataset) const;
  std::optional<std::string> attr_string(const std::string& object, const std::string& name) const;
  std::optional<double> attr_double(const std::string& object, const std::string& name) const;
  std::vector<std::string> children(const std::string& group) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace pnc::h5
