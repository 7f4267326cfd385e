#include "pnc/core/hdf5_io.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/version.hpp"

#include <H5Cpp.h>

#include <filesystem>

namespace pnc::h5 {

struct File::Impl {
  std::string path;
  H5::H5File file;
};

namespace {
std::vector<std::string> split_path(const std::string& p) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : p) {
    if (c == '/') {
      if (!cur.empty()) parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) parts.push_back(cur);
  return parts;
}

void ensure_parents(H5::H5File& f, const std::string& dataset) {
  auto parts = split_path(dataset);
  std::string cur;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    cur += "/" + parts[i];
    if (!f.nameExists(cur)) f.createGroup(cur);
  }
}

struct ObjectHolder {
  std::optional<H5::Group> group;
  std::optional<H5::DataSet> dataset;
  H5::H5Object* get() {
    if (group) return &*group;
    return &*dataset;
  }
};

H5::H5Object* open_object(H5::H5File& f, const std::string& name, ObjectHolder& holder) {
  if (name == "/" || name.empty()) {
    holder.group.emplace(f.openGroup("/"));
  } else {
    H5O_info_t info;
    if (H5Oget_info_by_name(f.getId(), name.c_str(), &info, H5P_DEFAULT) < 0)
      throw H5::Exception("H5Oget_info_by_name", "cannot read the object header");
    if (info.type == H5O_TYPE_GROUP)
      holder.group.emplace(f.openGroup(name));
    else if (info.type == H5O_TYPE_DATASET)
      holder.dataset.emplace(f.openDataSet(name));
    else
      throw H5::Exception("open_object", "neither a group nor a dataset");
  }
  return holder.get();
}

// A corrupt file makes the HDF5 C++ API throw H5::Exception (not a std::exception) from calls
// as innocent as nameExists(): every read turns it into an InputError naming file and object.
template <class F>
auto guarded(const std::string& file, const std::string& object, const char* what, F&& f) {
  try {
    return f();
  } catch (const H5::Exception& e) {
    fail(file, object, "", std::string(what) + ": " + e.getDetailMsg());
  }
}

// Largest dataset pnc reads (elements): 2^27 doubles = 1 GiB. A corrupt or hostile header can
// declare any extent in a tiny file; this bounds what one read may allocate.
constexpr hsize_t kMaxElements = hsize_t(1) << 27;
} // namespace

File::File(const std::string& path, Mode mode) : impl_(std::make_unique<Impl>()) {
  H5::Exception::dontPrint();
  impl_->path = path;
  try {
    if (mode == Mode::read) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec))
        fail(path, "", "", "cannot open: no such file");
      if (!H5::H5File::isHdf5(path)) fail(path, "", "", "not an HDF5 file");
      impl_->file = H5::H5File(path, H5F_ACC_RDONLY);
    } else {
      impl_->file = H5::H5File(path, H5F_ACC_TRUNC);
    }
  } catch (const H5::Exception& e) {
    fail(path, "", "", "cannot open HDF5 file: " + e.getDetailMsg());
  }
}
File::~File() = default;
File::File(File&&) noexcept = default;
File& File::operator=(File&&) noexcept = default;
const std::string& File::path() const {
  return impl_->path;
}

void File::write_scalar(const std::string& dataset, double value) {
  ensure_parents(impl_->file, dataset);
  H5::DataSet ds =
      impl_->file.createDataSet(dataset, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
  ds.write(&value, H5::PredType::NATIVE_DOUBLE);
}

void File::write_matrix(const std::string& dataset, const RowMatrix& m) {
  ensure_parents(impl_->file, dataset);
  hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  H5::DataSet ds =
      impl_->file.createDataSet(dataset, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(2, dims));
  if (m.size() > 0) ds.write(m.data(), H5::PredType::NATIVE_DOUBLE);
}

void File::write_vector(const std::string& dataset, const std::vector<double>& v) {
  ensure_parents(impl_->file, dataset);
  hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
  H5::DataSet ds =
      impl_->file.createDataSet(dataset, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, dims));
  if (!v.empty()) ds.write(v.data(), H5::PredType::NATIVE_DOUBLE);
}

void File::write_string(const std::string& dataset, const std::string& text) {
  ensure_parents(impl_->file, dataset);
  H5::StrType st(H5::PredType::C_S1, H5T_VARIABLE);
  H5::DataSet ds = impl_->file.createDataSet(dataset, st, H5::DataSpace(H5S_SCALAR));
  ds.write(text, st);
}

void File::set_attr(const std::string& object, const std::string& name, const std::string& value) {
  ObjectHolder h;
  H5::H5Object* o = open_object(impl_->file, object, h);
  H5::StrType st(H5::PredType::C_S1, H5T_VARIABLE);
  if (o->attrExists(name)) o->removeAttr(name);
  H5::Attribute a = o->createAttribute(name, st, H5::DataSpace(H5S_SCALAR));
  a.write(st, value);
}

void File::set_attr(const std::string& object, const std::string& name, double value) {
  ObjectHolder h;
  H5::H5Object* o = open_object(impl_->file, object, h);
  if (o->attrExists(name)) o->removeAttr(name);
  H5::Attribute a =
      o->createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_DOUBLE, &value);
}

void File::write_integer(const std::string& dataset, std::int64_t value) {
  ensure_parents(impl_->file, dataset);
  H5::DataSet ds =
      impl_->file.createDataSet(dataset, H5::PredType::STD_I64LE, H5::DataSpace(H5S_SCALAR));
  ds.write(&value, H5::PredType::NATIVE_INT64);
}

void File::write_integers(const std::string& dataset, const std::vector<std::int64_t>& v) {
  ensure_parents(impl_->file, dataset);
  hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
  H5::DataSet ds =
      impl_->file.createDataSet(dataset, H5::PredType::STD_I64LE, H5::DataSpace(1, dims));
  if (!v.empty()) ds.write(v.data(), H5::PredType::NATIVE_INT64);
}

void File::set_attr_integer(const std::string& object, const std::string& name,
                            std::int64_t value) {
  ObjectHolder h;
  H5::H5Object* o = open_object(impl_->file, object, h);
  if (o->attrExists(name)) o->removeAttr(name);
  H5::Attribute a = o->createAttribute(name, H5::PredType::STD_I64LE, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_INT64, &value);
}

bool File::exists(const std::string& object) const {
  return guarded(impl_->path, object, "cannot look up the object (corrupt file?)", [&] {
    auto parts = split_path(object);
    std::string cur;
    for (const auto& p : parts) {
      cur += "/" + p;
      if (!impl_->file.nameExists(cur)) return false;
    }
    return true;
  });
}

namespace {
[[noreturn]] void missing(const std::string& file, const std::string& ds) {
  fail(file, ds, "", "required dataset is missing");
}
} // namespace

double File::read_scalar(const std::string& dataset) const {
  if (!exists(dataset)) missing(impl_->path, dataset);
  try {
    H5::DataSet ds = impl_->file.openDataSet(dataset);
    if (ds.getSpace().getSimpleExtentNpoints() != 1)
      fail(impl_->path, dataset, "", "expected a scalar dataset");
    double v = 0;
    ds.read(&v, H5::PredType::NATIVE_DOUBLE);
    return v;
  } catch (const H5::Exception& e) {
    fail(impl_->path, dataset, "", "cannot read as a number: " + e.getDetailMsg());
  }
}

bool File::is_integer(const std::string& dataset) const {
  if (!exists(dataset)) return false;
  return guarded(impl_->path, dataset, "cannot open the dataset",
                 [&] { return impl_->file.openDataSet(dataset).getTypeClass() == H5T_INTEGER; });
}

std::int64_t File::read_integer(const std::string& dataset) const {
  if (!exists(dataset)) missing(impl_->path, dataset);
  if (!is_integer(dataset)) fail(impl_->path, dataset, "", "expected an integer dataset");
  try {
    H5::DataSet ds = impl_->file.openDataSet(dataset);
    if (ds.getSpace().getSimpleExtentNpoints() != 1)
      fail(impl_->path, dataset, "", "expected a scalar dataset");
    std::int64_t v = 0;
    ds.read(&v, H5::PredType::NATIVE_INT64);
    return v;
  } catch (const H5::Exception& e) {
    fail(impl_->path, dataset, "", "cannot read as an integer: " + e.getDetailMsg());
  }
}

RowMatrix File::read_matrix(const std::string& dataset) const {
  if (!exists(dataset)) missing(impl_->path, dataset);
  try {
    H5::DataSet ds = impl_->file.openDataSet(dataset);
    H5::DataSpace sp = ds.getSpace();
    if (sp.getSimpleExtentNdims() != 2) fail(impl_->path, dataset, "", "expected a 2-D dataset");
    hsize_t dims[2];
    sp.getSimpleExtentDims(dims);
    if (dims[0] > kMaxElements || dims[1] > kMaxElements ||
        (dims[1] > 0 && dims[0] > kMaxElements / dims[1]))
      fail(impl_->path, dataset, std::to_string(dims[0]) + "x" + std::to_string(dims[1]),
           "dataset too large (at most 2^27 elements)");
    RowMatrix m(static_cast<Eigen::Index>(dims[0]), static_cast<Eigen::Index>(dims[1]));
    if (m.size() > 0) ds.read(m.data(), H5::PredType::NATIVE_DOUBLE);
    return m;
  } catch (const H5::Exception& e) {
    fail(impl_->path, dataset, "", "cannot read as a matrix: " + e.getDetailMsg());
  }
}

std::vector<double> File::read_vector(const std::string& dataset) const {
  if (!exists(dataset)) missing(impl_->path, dataset);
  try {
    H5::DataSet ds = impl_->file.openDataSet(dataset);
    const hssize_t n = ds.getSpace().getSimpleExtentNpoints();
    if (n < 0 || static_cast<hsize_t>(n) > kMaxElements)
      fail(impl_->path, dataset, std::to_string(n), "dataset too large (at most 2^27 elements)");
    std::vector<double> v(static_cast<std::size_t>(n));
    if (!v.empty()) ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
    return v;
  } catch (const H5::Exception& e) {
    fail(impl_->path, dataset, "", "cannot read as a vector: " + e.getDetailMsg());
  }
}

std::string File::read_string(const std::string& dataset) const {
  if (!exists(dataset)) missing(impl_->path, dataset);
  try {
    H5::DataSet ds = impl_->file.openDataSet(dataset);
    // as for attributes: HDF5 would read every element into the one string
    if (ds.getSpace().getSimpleExtentNpoints() != 1)
      fail(impl_->path, dataset, "", "expected a single text value");
    std::string s;
    ds.read(s, ds.getStrType());
    return s;
  } catch (const H5::Exception& e) {
    fail(impl_->path, dataset, "", "cannot read as text: " + e.getDetailMsg());
  }
}

std::optional<std::string> File::attr_string(const std::string& object,
                                             const std::string& name) const {
  if (!exists(object) && object != "/") return std::nullopt;
  try {
    ObjectHolder h;
    H5::H5Object* o = open_object(impl_->file, object, h);
    if (!o->attrExists(name)) return std::nullopt;
    H5::Attribute a = o->openAttribute(name);
    // HDF5 reads every element into the one string: only a single element is safe to read
    if (a.getSpace().getSimpleExtentNpoints() != 1)
      fail(impl_->path, object + "@" + name, "", "attribute must be a single text value");
    std::string s;
    a.read(a.getStrType(), s);
    return s;
  } catch (const H5::Exception& e) {
    fail(impl_->path, object + "@" + name, "", "attribute must be text: " + e.getDetailMsg());
  }
}

std::optional<double> File::attr_double(const std::string& object, const std::string& name) const {
  if (!exists(object) && object != "/") return std::nullopt;
  try {
    ObjectHolder h;
    H5::H5Object* o = open_object(impl_->file, object, h);
    if (!o->attrExists(name)) return std::nullopt;
    H5::Attribute a = o->openAttribute(name);
    if (a.getTypeClass() != H5T_FLOAT && a.getTypeClass() != H5T_INTEGER)
      fail(impl_->path, object + "@" + name, "", "attribute must be a number");
    if (a.getSpace().getSimpleExtentNpoints() != 1)
      fail(impl_->path, object + "@" + name, "", "attribute must be a single number");
    double v = 0;
    a.read(H5::PredType::NATIVE_DOUBLE, &v);
    return v;
  } catch (const H5::Exception& e) {
    fail(impl_->path, object + "@" + name, "", "attribute must be a number: " + e.getDetailMsg());
  }
}

std::vector<std::string> File::children(const std::string& group) const {
  std::vector<std::string> out;
  if (!exists(group) && group != "/") return out;
  return guarded(impl_->path, group, "cannot list the group", [&] {
    H5::Group g = impl_->file.openGroup(group);
    for (hsize_t i = 0; i < g.getNumObjs(); ++i)
      out.push_back(g.getObjnameByIdx(i));
    return out;
  });
}

void write_provenance(File& f, const std::string& command) {
  const std::string cmd = !command.empty()        ? command
                          : !invocation().empty() ? invocation()
                                                  : "(not run from the pnc command)";
  f.set_attr("/", "software", version_string());
  f.write_string("/provenance/software", version_string());
  f.set_attr("/provenance", "created", utc_timestamp());
  f.set_attr("/provenance", "command", cmd);
}

} // namespace pnc::h5
