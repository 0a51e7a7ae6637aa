// Attributes: numbers, arrays of numbers and strings on a group or dataset (Hdf5.h). A read
// checks the attribute's class and count before HDF5 converts it (an integer read refuses a
// float rather than truncate it), and a variable-length string's heap object before HDF5 copies
// it (checkHeapString, Hdf5HeapCheck.cpp): a damaged or foreign attribute is an Error naming it.
#include <algorithm>
#include <string>
#include <vector>

#include "io/cache/Hdf5.h"

namespace sph::io::cache::h5 {

namespace {

void writeScalar(hid_t obj, const std::string& name, hid_t fileType, hid_t memType,
                 const void* value) {
  Handle space = checked(H5Screate(H5S_SCALAR), "create a dataspace");
  Handle attr =
      checked(H5Acreate2(obj, name.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "create attribute '" + name + "'");
  check(H5Awrite(attr.get(), memType, value), "write attribute '" + name + "'");
}

void writeArray(hid_t obj, const std::string& name, hid_t fileType, hid_t memType,
                const void* values, std::size_t n) {
  const hsize_t dims[1] = {n};
  Handle space =
      checked(n ? H5Screate_simple(1, dims, nullptr) : H5Screate(H5S_NULL), "create a dataspace");
  Handle attr =
      checked(H5Acreate2(obj, name.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "create attribute '" + name + "'");
  if (n) check(H5Awrite(attr.get(), memType, values), "write attribute '" + name + "'");
}

// A fixed-length, NUL-terminated UTF-8 string type holding `length` characters.
Handle stringType(std::size_t length) {
  Handle type = checked(H5Tcopy(H5T_C_S1), "copy the string type");
  check(H5Tset_size(type.get(), length + 1), "size a string type");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), "terminate a string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8");
  return type;
}

Handle openAttribute(hid_t obj, const std::string& name) {
  return checked(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute '" + name + "'");
}

// Element count of an attribute that must hold numbers of class `cls` (integer or float).
std::size_t numericAttribute(hid_t attr, const std::string& name, bool allowFloat, bool allowInt) {
  Handle type = checked(H5Aget_type(attr), "read the type of attribute '" + name + "'");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (!((allowFloat && cls == H5T_FLOAT) || (allowInt && cls == H5T_INTEGER))) {
    throw Error("attribute '" + name + "' is not " + (allowFloat ? "a number" : "an integer"), "");
  }
  Handle space = checked(H5Aget_space(attr), "read the shape of attribute '" + name + "'");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  check(n, "count attribute '" + name + "'");
  return static_cast<std::size_t>(n);
}

template <class T>
T readNumber(hid_t obj, const std::string& name, hid_t memType, bool allowFloat) {
  Handle attr = openAttribute(obj, name);
  if (numericAttribute(attr.get(), name, allowFloat, true) != 1) {
    throw Error("attribute '" + name + "' is not a single number", "");
  }
  T value{};
  check(H5Aread(attr.get(), memType, &value), "read attribute '" + name + "'");
  return value;
}

template <class T>
std::vector<T> readNumbers(hid_t obj, const std::string& name, hid_t memType, bool allowFloat) {
  Handle attr = openAttribute(obj, name);
  std::vector<T> values(numericAttribute(attr.get(), name, allowFloat, true));
  if (!values.empty())
    check(H5Aread(attr.get(), memType, values.data()), "read attribute '" + name + "'");
  return values;
}

}  // namespace

void writeAttribute(hid_t obj, const std::string& name, const std::string& value) {
  Handle type = checked(H5Tcopy(H5T_C_S1), "copy the string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), "make a variable-length string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8");
  const char* text = value.c_str();
  writeScalar(obj, name, type.get(), type.get(), &text);
}

void writeFixedAttribute(hid_t obj, const std::string& name, const std::string& value,
                         std::size_t width) {
  const std::size_t length = std::max(width, value.size());
  Handle type = stringType(length);
  std::string padded = value;
  padded.resize(length + 1, '\0');
  writeScalar(obj, name, type.get(), type.get(), padded.data());
}

void writeAttribute(hid_t obj, const std::string& name, double value) {
  writeScalar(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}
void writeAttribute(hid_t obj, const std::string& name, float value) {
  writeScalar(obj, name, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, &value);
}
void writeAttribute(hid_t obj, const std::string& name, std::int64_t value) {
  writeScalar(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
}
void writeAttribute(hid_t obj, const std::string& name, std::uint64_t value) {
  writeScalar(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value);
}
void writeAttribute(hid_t obj, const std::string& name, const std::vector<double>& values) {
  writeArray(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.data(), values.size());
}
void writeAttribute(hid_t obj, const std::string& name, const std::vector<std::uint64_t>& values) {
  writeArray(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, values.data(), values.size());
}

void rewriteAttribute(hid_t obj, const std::string& name, const std::string& value) {
  Handle attr = openAttribute(obj, name);
  Handle type = checked(H5Aget_type(attr.get()), "read the type of attribute '" + name + "'");
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    throw Error("attribute '" + name + "' is not a fixed-length string", "");
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string padded = value.substr(0, size > 0 ? size - 1 : 0);
  padded.resize(size, '\0');
  check(H5Awrite(attr.get(), type.get(), padded.data()), "write attribute '" + name + "'");
}

std::string readStringAttribute(hid_t obj, const std::string& name) {
  Handle attr = openAttribute(obj, name);
  Handle type = checked(H5Aget_type(attr.get()), "read the type of attribute '" + name + "'");
  if (H5Tget_class(type.get()) != H5T_STRING)
    throw Error("attribute '" + name + "' is not a string", "");
  Handle space = checked(H5Aget_space(attr.get()), "read the shape of attribute '" + name + "'");
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    throw Error("attribute '" + name + "' is not one string", "");
  if (H5Tis_variable_str(type.get()) > 0) {
    checkHeapString(obj, name);
    // Read with the attribute's own type: its character set (UTF-8 or ASCII) is kept as it is.
    char* text = nullptr;
    check(H5Aread(attr.get(), type.get(), &text), "read attribute '" + name + "'");
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string value(H5Tget_size(type.get()), '\0');
  check(H5Aread(attr.get(), type.get(), value.data()), "read attribute '" + name + "'");
  value.resize(value.find('\0') == std::string::npos ? value.size() : value.find('\0'));
  return value;
}

double readDoubleAttribute(hid_t obj, const std::string& name) {
  return readNumber<double>(obj, name, H5T_NATIVE_DOUBLE, true);
}
float readFloatAttribute(hid_t obj, const std::string& name) {
  return readNumber<float>(obj, name, H5T_NATIVE_FLOAT, true);
}
std::int64_t readIntAttribute(hid_t obj, const std::string& name) {
  return readNumber<std::int64_t>(obj, name, H5T_NATIVE_INT64, false);
}
std::uint64_t readUintAttribute(hid_t obj, const std::string& name) {
  return readNumber<std::uint64_t>(obj, name, H5T_NATIVE_UINT64, false);
}
std::vector<double> readDoubleArrayAttribute(hid_t obj, const std::string& name) {
  return readNumbers<double>(obj, name, H5T_NATIVE_DOUBLE, true);
}
std::vector<std::uint64_t> readUintArrayAttribute(hid_t obj, const std::string& name) {
  return readNumbers<std::uint64_t>(obj, name, H5T_NATIVE_UINT64, false);
}

std::vector<std::string> attributeNames(hid_t obj) {
  std::vector<std::string> names;
  H5O_info_t info;
  check(H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS), "count attributes");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const ssize_t len =
        H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    check(len, "read an attribute name");
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    check(H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                             H5P_DEFAULT),
          "read an attribute name");
    name.resize(static_cast<std::size_t>(len));
    names.push_back(name);
  }
  return names;
}

}  // namespace sph::io::cache::h5
