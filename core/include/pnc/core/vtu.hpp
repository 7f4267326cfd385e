#pragma once
// pnc/core/vtu.hpp: point-cloud VTU frames and PVD collections that ParaView (5.11, VTK 9)
// reads with units and tensors intact, without pnc's documentation (D236).
//
// VTU: VTK XML UnstructuredGrid, version 0.1, one VTK_VERTEX cell per point, byte order
// LittleEndian, header_type UInt32. Every DataArray is either ASCII (decimal text, the
// precision given) or inline "binary": base64 (RFC 4648) of a UInt32 byte count followed by
// the raw little-endian values (Float64 or Int32), not compressed.
//  - Points: positions in metres (m), 3 components (2-D data has z = 0).
//  - Point arrays: 1 component (scalar), 3 (vector x y z), 6 (symmetric tensor in VTK's
//    order XX YY ZZ XY YZ XZ: the order of vtkMath::TensorFromSymmetricTensor in
//    VTK 9 Common/Core/vtkMath.h, which ParaView's tensor filters use for 6-component
//    arrays) or 9 (full tensor, row-major XX XY XZ YX YY YZ ZX ZY ZZ). The unit is part of the
//    name, after the last '_' ("stress_Pa", "displacement_m", "velocity_m_per_s", "_1" for
//    dimensionless, "_index" for integer labels).
//  - Field data: one Float64 scalar per entry (named with its unit, e.g. "time_s",
//    "load_N"), and the String array "units" that lists "array=unit" for every point array
//    and field scalar, so the units survive filters that rename arrays.
// PVD: VTK XML Collection; one DataSet per frame with `timestep` (a pseudo-time that
// increases strictly: the physical time when it does, else the step index or the arc length
// of the loading path), part 0 and the file relative to the PVD's folder. The physical
// time/load of each frame is field data of its VTU.
// Files are written atomically (atomic_file.hpp). Bad arguments (an array whose size is not
// points x components, a component count other than 1/3/6/9, a timestep that does not
// increase, a name or unit with characters XML would need escaped or with '=', a precision
// outside 1-17, base64 arrays over 4 GiB) throw pnc::InputError naming the output file, the
// array or entry, the value and the rule.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pnc::vtu {

enum class Encoding { ascii, base64 };

/// One point array: values point-major (`components` per point), or integer `labels` (one per
/// point; then `values` is empty and `components` 1).
struct PointArray {
  std::string name;   ///< with the unit suffix: "stress_Pa", "material_index"
  std::string unit;   ///< SI unit text ("Pa", "m", "m/s", "1", "index")
  int components = 1; ///< 1, 3, 6 (XX YY ZZ XY YZ XZ) or 9 (row-major)
  std::vector<double> values;
  std::vector<std::int32_t> labels;
};

/// One field-data scalar of a frame (the physical time, the load).
struct FieldScalar {
  std::string name; ///< with the unit suffix: "time_s", "load_N"
  std::string unit; ///< SI unit text
  double value = 0.0;
};

struct Frame {
  std::vector<std::array<double, 3>> points; ///< positions, m
  std::vector<PointArray> arrays;
  std::vector<FieldScalar> field;
  std::string comment; ///< an XML comment ("--" written "- -"); e.g. the software version
};

struct Options {
  Encoding encoding = Encoding::ascii;
  int precision = 17; ///< significant digits of ASCII values (17 round-trips a double)
};

/// Writes `frame` as a VTU file at `path`, atomically. Throws InputError (above).
void write_vtu(const std::string& path, const Frame& frame, const Options& options = {});

/// One PVD entry: the VTU's path relative to the PVD's folder and its pseudo-time.
struct PvdEntry {
  std::string file;
  double timestep = 0.0;
};

/// Writes the PVD collection at `path`, atomically. Throws InputError unless the timesteps
/// are finite and strictly increasing.
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

/// The 6 components XX YY ZZ XY YZ XZ of a symmetric 3x3 tensor given row-major (9 values;
/// the upper triangle is taken).
std::array<double, 6> symmetric6(const double* row_major9);

} // namespace pnc::vtu
