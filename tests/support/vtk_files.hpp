#pragma once
// Reading the field files back in the tests, independently of the writers: an ASCII .vtu by
// its XML text (the numbers parsed by strtod/strtoll, which the writer's shortest round-trip
// form makes exact), a VTKHDF file through HDF5's C API. Both give every array as the bytes of
// its values in the host's order, keyed as the .vtu names them: "Points", "Cells/connectivity",
// "Cells/offsets" (each cell's end), "Cells/types", "PointData/<name>", "CellData/<name>",
// so that the two formats compare bit for bit.
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/cli.hpp"

#if TC_HAVE_HDF5
#include <hdf5.h>
#endif

namespace tc::test {

struct VtkArray {
  std::string type;  // "Float64", "Int64" or "UInt8"
  int components = 1;
  std::vector<unsigned char> bytes;
  [[nodiscard]] size_t element_size() const { return type == "UInt8" ? 1 : 8; }
  [[nodiscard]] size_t rows() const { return bytes.size() / element_size() / components; }
  [[nodiscard]] double value(size_t i) const {  // the i-th number, whatever its type
    if (type == "Float64") {
      double v = 0;
      std::memcpy(&v, bytes.data() + 8 * i, 8);
      return v;
    }
    if (type == "Int64") {
      std::int64_t v = 0;
      std::memcpy(&v, bytes.data() + 8 * i, 8);
      return static_cast<double>(v);
    }
    return bytes[i];
  }
};
using VtkArrays = std::map<std::string, VtkArray>;

inline std::vector<unsigned char> ascii_bytes(const std::string& type, const std::string& text) {
  std::vector<unsigned char> out;
  const auto put = [&out](auto v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
  };
  const char* p = text.c_str();
  for (char* end = nullptr;; p = end) {
    if (type == "Float64") {
      const double v = std::strtod(p, &end);
      if (end == p) break;
      put(v);
    } else {
      const long long v = std::strtoll(p, &end, 10);
      if (end == p) break;
      if (type == "Int64")
        put(static_cast<std::int64_t>(v));
      else
        put(static_cast<std::uint8_t>(v));
    }
  }
  return out;
}

/// Every array of an ASCII .vtu (one piece).
inline VtkArrays read_ascii_vtu(const std::filesystem::path& path) {
  const auto xml = read_file(path);
  VtkArrays arrays;
  const std::regex tag(R"(<DataArray([^>]*)>)");
  const std::regex attribute(R"re((\w+)="([^"]*)")re");
  for (std::sregex_iterator it(xml.begin(), xml.end(), tag), e; it != e; ++it) {
    std::map<std::string, std::string> a;
    const std::string attributes = (*it)[1];
    for (std::sregex_iterator at(attributes.begin(), attributes.end(), attribute), ae; at != ae;
         ++at)
      a[(*at)[1]] = (*at)[2];
    if (a["format"] != "ascii") throw std::runtime_error(path.string() + ": not an ASCII .vtu");
    const auto where = static_cast<size_t>(it->position());
    std::string section = "Points";
    for (const char* s : {"<Cells>", "<PointData>", "<CellData>"})
      if (xml.rfind(s, where) != std::string::npos) section = std::string(s + 1, s + strlen(s) - 1);
    const auto start = where + static_cast<size_t>(it->length());
    VtkArray array{
        a["type"], a.count("NumberOfComponents") ? std::stoi(a["NumberOfComponents"]) : 1,
        ascii_bytes(a["type"], xml.substr(start, xml.find("</DataArray>", start) - start))};
    arrays[section == "Points" ? section : section + "/" + a["Name"]] = std::move(array);
  }
  return arrays;
}

#if TC_HAVE_HDF5

/// A VTKHDF file as read back: its attributes, the pieces' sizes and every array of the file
/// (the pieces' rows one after the other; "Cells/offsets" as stored, each piece's from 0).
struct VtkHdfFile {
  std::vector<long long> version;
  std::string type;
  std::vector<std::int64_t> n_points, n_cells, n_ids;
  VtkArrays arrays;

  /// Piece p's arrays as its .vtu holds them (offsets without their leading 0).
  [[nodiscard]] VtkArrays piece(size_t p) const {
    const auto before = [&](const std::vector<std::int64_t>& n) {
      std::int64_t s = 0;
      for (size_t q = 0; q < p; ++q) s += n[q];
      return static_cast<size_t>(s);
    };
    VtkArrays out;
    for (const auto& [key, array] : arrays) {
      size_t first = 0, rows = 0;
      if (key == "Points" || key.rfind("PointData/", 0) == 0) {
        first = before(n_points);
        rows = static_cast<size_t>(n_points[p]);
      } else if (key == "Cells/connectivity") {
        first = before(n_ids);
        rows = static_cast<size_t>(n_ids[p]);
      } else if (key == "Cells/offsets") {
        first = before(n_cells) + p + 1;  // the leading 0 left out
        rows = static_cast<size_t>(n_cells[p]);
      } else {
        first = before(n_cells);
        rows = static_cast<size_t>(n_cells[p]);
      }
      const size_t row = array.element_size() * static_cast<size_t>(array.components);
      VtkArray a{array.type, array.components, {}};
      a.bytes.assign(array.bytes.begin() + static_cast<long>(first * row),
                     array.bytes.begin() + static_cast<long>((first + rows) * row));
      out[key] = std::move(a);
    }
    return out;
  }
};

namespace vtkhdf_detail {

inline void require(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("VTKHDF read: " + what);
}

/// The data set `name` of `group` as bytes of `type`, the file's type checked to be `file_type`.
inline VtkArray read_set(hid_t group, const std::string& name, const std::string& type) {
  const hid_t set = H5Dopen2(group, name.c_str(), H5P_DEFAULT);
  require(set >= 0, "open " + name);
  const hid_t space = H5Dget_space(set);
  std::array<hsize_t, 2> dims{0, 1};
  const int rank = H5Sget_simple_extent_ndims(space);
  require(rank == 1 || rank == 2, name + ": rank");
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  const hid_t stored = H5Dget_type(set);
  const hid_t file_type = type == "Float64" ? H5T_IEEE_F64LE
                          : type == "Int64" ? H5T_STD_I64LE
                                            : H5T_STD_U8LE;
  require(H5Tequal(stored, file_type) > 0, name + ": stored as another type than " + type);
  const hid_t memory = type == "Float64" ? H5T_NATIVE_DOUBLE
                       : type == "Int64" ? H5T_NATIVE_INT64
                                         : H5T_NATIVE_UINT8;
  VtkArray a{type, rank == 2 ? static_cast<int>(dims[1]) : 1, {}};
  a.bytes.resize(static_cast<size_t>(dims[0] * (rank == 2 ? dims[1] : 1)) * a.element_size());
  if (!a.bytes.empty())
    require(H5Dread(set, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.bytes.data()) >= 0, name);
  H5Tclose(stored);
  H5Sclose(space);
  H5Dclose(set);
  return a;
}

inline std::vector<std::int64_t> read_counts(hid_t group, const std::string& name) {
  const auto a = read_set(group, name, "Int64");
  std::vector<std::int64_t> v(a.bytes.size() / 8);
  std::memcpy(v.data(), a.bytes.data(), a.bytes.size());
  return v;
}

inline std::vector<std::string> names(hid_t group) {
  std::vector<std::string> out;
  const auto add = [](hid_t, const char* name, const H5L_info_t*, void* list) -> herr_t {
    static_cast<std::vector<std::string>*>(list)->push_back(name);
    return 0;
  };
  H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, add, &out);
  return out;
}

}  // namespace vtkhdf_detail

/// A VTKHDF file read serially (HDF5's default driver).
inline VtkHdfFile read_vtkhdf(const std::filesystem::path& path) {
  using namespace vtkhdf_detail;
  VtkHdfFile f;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  require(file >= 0, "open " + path.string());
  const hid_t root = H5Gopen2(file, "/VTKHDF", H5P_DEFAULT);
  require(root >= 0, "no /VTKHDF group");
  const hid_t version = H5Aopen(root, "Version", H5P_DEFAULT);
  require(version >= 0, "no Version attribute");
  const hid_t vspace = H5Aget_space(version);
  f.version.resize(static_cast<size_t>(H5Sget_simple_extent_npoints(vspace)));
  H5Aread(version, H5T_NATIVE_LLONG, f.version.data());
  H5Sclose(vspace);
  H5Aclose(version);
  const hid_t type = H5Aopen(root, "Type", H5P_DEFAULT);
  require(type >= 0, "no Type attribute");
  const hid_t stored = H5Aget_type(type);
  require(H5Tget_class(stored) == H5T_STRING && H5Tis_variable_str(stored) == 0,
          "Type is not a fixed-length string");
  f.type.assign(H5Tget_size(stored), '\0');
  H5Aread(type, stored, f.type.data());
  f.type.resize(std::strlen(f.type.c_str()));  // without the null padding
  H5Tclose(stored);
  H5Aclose(type);
  f.n_points = read_counts(root, "NumberOfPoints");
  f.n_cells = read_counts(root, "NumberOfCells");
  f.n_ids = read_counts(root, "NumberOfConnectivityIds");
  f.arrays["Points"] = read_set(root, "Points", "Float64");
  f.arrays["Cells/connectivity"] = read_set(root, "Connectivity", "Int64");
  f.arrays["Cells/offsets"] = read_set(root, "Offsets", "Int64");
  f.arrays["Cells/types"] = read_set(root, "Types", "UInt8");
  for (const char* data : {"PointData", "CellData"}) {
    const hid_t group = H5Gopen2(root, data, H5P_DEFAULT);
    require(group >= 0, std::string("no ") + data);
    for (const auto& name : names(group))
      f.arrays[std::string(data) + "/" + name] = read_set(group, name, "Float64");
    H5Gclose(group);
  }
  H5Gclose(root);
  H5Fclose(file);
  return f;
}

#endif

}  // namespace tc::test
