#include "hdf5_io.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <new>

#include "taskmap/core/error.hpp"

namespace taskmap::h5 {
namespace {

// Datasets larger than this many elements are refused as corrupt (a garbage header must not
// make us allocate terabytes).
constexpr hsize_t kMaxElements = hsize_t{1} << 31;
// Chunks of about this many elements (128 KiB of doubles).
constexpr hsize_t kChunkElements = 16384;

hid_t fileType(Type type) {
  switch (type) {
    case Type::kF64:
      return H5T_IEEE_F64LE;
    case Type::kI64:
      return H5T_STD_I64LE;
    case Type::kI32:
      return H5T_STD_I32LE;
    case Type::kU8:
      return H5T_STD_U8LE;
  }
  return H5T_IEEE_F64LE;
}

hid_t memType(Type type) {
  switch (type) {
    case Type::kF64:
      return H5T_NATIVE_DOUBLE;
    case Type::kI64:
      return H5T_NATIVE_INT64;
    case Type::kI32:
      return H5T_NATIVE_INT32;
    case Type::kU8:
      return H5T_NATIVE_UINT8;
  }
  return H5T_NATIVE_DOUBLE;
}

Id vlenStringType() {
  Id t = checked(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create string type");
  check(H5Tset_size(t, H5T_VARIABLE), "cannot create string type");
  check(H5Tset_cset(t, H5T_CSET_UTF8), "cannot create string type");
  return t;
}

// Fixed-length UTF-8 string type of `size` bytes (at least 1), NUL-padded: stored inline in
// the object header, so no global heap is written.
Id fixedStringType(std::size_t size) {
  Id t = checked(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create string type");
  check(H5Tset_size(t, std::max<std::size_t>(1, size)), "cannot create string type");
  check(H5Tset_strpad(t, H5T_STR_NULLPAD), "cannot create string type");
  check(H5Tset_cset(t, H5T_CSET_UTF8), "cannot create string type");
  return t;
}

// Object creation properties shared by groups and datasets: no modification times, so that
// the same map gives the same bytes.
void untimed(hid_t ocpl, const std::string& name) {
  check(H5Pset_obj_track_times(ocpl, 0), "cannot turn off time tracking of " + name);
}

void writeScalarAttr(hid_t obj, const std::string& name, hid_t file_type, hid_t mem_type,
                     const void* value) {
  Id space = checked(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace");
  Id attr = checked(H5Acreate2(obj, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose, "cannot create attribute " + name);
  check(H5Awrite(attr, mem_type, value), "cannot write attribute " + name);
}

Id openAttr(hid_t obj, const std::string& where, const std::string& name) {
  if (H5Aexists(obj, name.c_str()) <= 0) throw Error("missing attribute " + name + " on " + where);
  return checked(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose,
                 "cannot open attribute " + name + " on " + where);
}

// Number of elements of an attribute's dataspace.
hssize_t attrElements(hid_t attr, const std::string& label) {
  Id space = checked(H5Aget_space(attr), H5Sclose, "cannot read the shape of " + label);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0) throw Error("cannot read the shape of " + label);
  return n;
}

H5T_class_t attrClass(hid_t attr, const std::string& label) {
  Id type = checked(H5Aget_type(attr), H5Tclose, "cannot read the type of " + label);
  return H5Tget_class(type);
}

template <typename T>
T readScalarNumber(hid_t obj, const std::string& where, const std::string& name, hid_t mem_type,
                   bool allow_float) {
  const std::string label = "attribute " + name + " on " + where;
  Id attr = openAttr(obj, where, name);
  const H5T_class_t cls = attrClass(attr, label);
  if (cls != H5T_INTEGER && !(allow_float && cls == H5T_FLOAT))
    throw Error(label + " must be " + (allow_float ? "a number" : "an integer"));
  if (attrElements(attr, label) != 1) throw Error(label + " must be a single value");
  T value{};
  check(H5Aread(attr, mem_type, &value), "cannot read " + label);
  return value;
}

struct Opened {
  Id dataset;
  std::vector<hsize_t> dims;
  H5T_class_t cls = H5T_NO_CLASS;
  hsize_t elements = 0;
};

Opened openDataset(hid_t file, const std::string& path, int rank, std::size_t cols) {
  if (!exists(file, path)) throw Error("missing dataset " + path);
  Opened o;
  o.dataset =
      checked(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "cannot open dataset " + path);
  Id space = checked(H5Dget_space(o.dataset), H5Sclose, "cannot read the shape of " + path);
  const int r = H5Sget_simple_extent_ndims(space);
  if (r != rank)
    throw Error("dataset " + path + " has rank " + std::to_string(r) + ", expected " +
                std::to_string(rank));
  o.dims.resize(static_cast<std::size_t>(rank));
  check(H5Sget_simple_extent_dims(space, o.dims.data(), nullptr),
        "cannot read the shape of " + path);
  if (rank == 2 && cols > 0 && o.dims[1] != cols)
    throw Error("dataset " + path + " has " + std::to_string(o.dims[1]) + " columns, expected " +
                std::to_string(cols));
  o.elements = 1;
  for (hsize_t d : o.dims) {
    if (d != 0 && o.elements > kMaxElements / d)
      throw Error("dataset " + path + " is absurdly large");
    o.elements *= d;
  }
  if (o.elements > kMaxElements) throw Error("dataset " + path + " is absurdly large");
  Id type = checked(H5Dget_type(o.dataset), H5Tclose, "cannot read the type of " + path);
  o.cls = H5Tget_class(type);
  return o;
}

template <typename T>
Array<T> readArray(hid_t file, const std::string& path, int rank, std::size_t cols, hid_t mem_type,
                   bool allow_float) {
  Opened o = openDataset(file, path, rank, cols);
  if (o.cls != H5T_INTEGER && !(allow_float && o.cls == H5T_FLOAT))
    throw Error("dataset " + path + " must hold " + (allow_float ? "numbers" : "integers"));
  Array<T> a;
  a.dims = o.dims;
  try {
    a.values.resize(static_cast<std::size_t>(o.elements));
  } catch (const std::bad_alloc&) {
    throw Error("dataset " + path + " is too large to read");
  }
  if (o.elements > 0)
    check(H5Dread(o.dataset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()),
          "cannot read dataset " + path + " (file damaged?)");
  return a;
}

// File-image callbacks that hand HDF5 the caller's buffer instead of copies (the pattern of
// HDF5's own H5LTopen_file_image with DONT_COPY | DONT_RELEASE, for a read-only image).
// HDF5 copies and frees the udata with the property lists and the file; the last free
// deletes it (all under hdf5Mutex()).
struct ImageRef {
  void* data;
  std::size_t size;
  int owners;
};

void* imageMalloc(std::size_t size, H5FD_file_image_op_t /*op*/, void* udata) {
  auto* ref = static_cast<ImageRef*>(udata);
  return size == ref->size ? ref->data : nullptr;
}

void* imageMemcpy(void* dest, const void* src, std::size_t size, H5FD_file_image_op_t /*op*/,
                  void* /*udata*/) {
  if (dest != src) std::memmove(dest, src, size);
  return dest;
}

void* imageRealloc(void* /*ptr*/, std::size_t /*size*/, H5FD_file_image_op_t /*op*/,
                   void* /*udata*/) {
  return nullptr;  // the image is read-only: HDF5 never needs to grow it
}

herr_t imageFree(void* /*ptr*/, H5FD_file_image_op_t /*op*/, void* /*udata*/) {
  return 0;
}

void* imageUdataCopy(void* udata) {
  ++static_cast<ImageRef*>(udata)->owners;
  return udata;
}

herr_t imageUdataFree(void* udata) {
  auto* ref = static_cast<ImageRef*>(udata);
  if (--ref->owners == 0) delete ref;
  return 0;
}

}  // namespace

Id mapFileAccess() {
  Id fapl = checked(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create property list");
  check(H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110),
        "cannot set the file-format bounds");
  return fapl;
}

Id mapFileCreation(std::size_t user_block) {
  Id fcpl = checked(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create property list");
  check(H5Pset_userblock(fcpl, user_block), "cannot reserve the user block");
  untimed(fcpl, "/");
  return fcpl;
}

Id openImage(const std::string& bytes, const std::string& what) {
  // The file is opened read-only, so HDF5 never writes through the cast-away const.
  auto* ref = new ImageRef{const_cast<char*>(bytes.data()), bytes.size(), 1};
  struct Release {
    ImageRef* ref;
    ~Release() { imageUdataFree(ref); }
  } release{ref};
  Id fapl = checked(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, what);
  check(H5Pset_fapl_core(fapl, 64 * 1024, 0), what);
  H5FD_file_image_callbacks_t callbacks = {imageMalloc,    imageMemcpy,    imageRealloc, imageFree,
                                           imageUdataCopy, imageUdataFree, ref};
  check(H5Pset_file_image_callbacks(fapl, &callbacks), what);
  check(H5Pset_file_image(fapl, ref->data, ref->size), what);
  return checked(H5Fopen("taskmap-image", H5F_ACC_RDONLY, fapl), H5Fclose, what);
}

std::mutex& hdf5Mutex() {
  static std::mutex mutex;
  return mutex;
}

void silenceErrors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Id& Id::operator=(Id&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = other.id_;
    closer_ = other.closer_;
    other.id_ = -1;
  }
  return *this;
}

bool Id::reset() {
  bool ok = true;
  if (id_ >= 0 && closer_ != nullptr) ok = closer_(id_) >= 0;
  id_ = -1;
  return ok;
}

Id checked(hid_t id, Id::Closer closer, const std::string& what) {
  if (id < 0) throw Error(what);
  return Id(id, closer);
}

void check(herr_t status, const std::string& what) {
  if (status < 0) throw Error(what);
}

Id createGroup(hid_t loc, const std::string& name) {
  Id gcpl = checked(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, "cannot create property list");
  untimed(gcpl, name);
  return checked(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), H5Gclose,
                 "cannot create group " + name);
}

void writeAttr(hid_t obj, const std::string& name, const std::string& value) {
  Id type = fixedStringType(value.size());
  std::string padded = value;
  padded.resize(std::max<std::size_t>(1, value.size()), '\0');
  writeScalarAttr(obj, name, type, type, padded.data());
}

void writeAttr(hid_t obj, const std::string& name, double value) {
  writeScalarAttr(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

void writeAttrInt(hid_t obj, const std::string& name, std::int64_t value) {
  writeScalarAttr(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
}

void writeAttrUInt(hid_t obj, const std::string& name, std::uint64_t value) {
  writeScalarAttr(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value);
}

void writeAttrU8(hid_t obj, const std::string& name, std::uint8_t value) {
  writeScalarAttr(obj, name, H5T_STD_U8LE, H5T_NATIVE_UINT8, &value);
}

void writeAttrVector(hid_t obj, const std::string& name, const double* values, std::size_t n) {
  const hsize_t dims[1] = {n};
  Id space = checked(H5Screate_simple(1, dims, nullptr), H5Sclose, "cannot create dataspace");
  Id attr = checked(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose, "cannot create attribute " + name);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, values), "cannot write attribute " + name);
}

namespace {

void writeArray(hid_t loc, const std::string& name, Type type, const void* data, int rank,
                const hsize_t* dims) {
  Id space = checked(H5Screate_simple(rank, dims, nullptr), H5Sclose, "cannot create dataspace");
  Id dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "cannot create property list");
  untimed(dcpl, name);
  const hsize_t rows = dims[0];
  const hsize_t width = rank == 2 ? dims[1] : 1;
  const bool empty = rows == 0 || width == 0;
  if (!empty) {
    const hsize_t chunk_rows =
        std::min<hsize_t>(rows, std::max<hsize_t>(1, kChunkElements / width));
    const hsize_t chunk[2] = {chunk_rows, width};
    check(H5Pset_chunk(dcpl, rank, chunk), "cannot set chunking of " + name);
    check(H5Pset_shuffle(dcpl), "cannot set the shuffle filter of " + name);
    check(H5Pset_deflate(dcpl, 4), "cannot set compression of " + name);
    check(H5Pset_fletcher32(dcpl), "cannot set the checksum filter of " + name);
  }
  Id dset =
      checked(H5Dcreate2(loc, name.c_str(), fileType(type), space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
              H5Dclose, "cannot create dataset " + name);
  if (!empty)
    check(H5Dwrite(dset, memType(type), H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "cannot write dataset " + name);
}

}  // namespace

void writeDataset(hid_t loc, const std::string& name, Type type, const void* data, std::size_t rows,
                  std::size_t cols) {
  const hsize_t dims[2] = {rows, cols};
  writeArray(loc, name, type, data, 2, dims);
}

void writeVector(hid_t loc, const std::string& name, Type type, const void* data, std::size_t n) {
  const hsize_t dims[1] = {n};
  writeArray(loc, name, type, data, 1, dims);
}

void writeStrings(hid_t loc, const std::string& name, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  Id type = fixedStringType(width);
  const hsize_t dims[1] = {values.size()};
  Id space = checked(H5Screate_simple(1, dims, nullptr), H5Sclose, "cannot create dataspace");
  Id dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "cannot create property list");
  untimed(dcpl, name);
  Id dset = checked(H5Dcreate2(loc, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                    H5Dclose, "cannot create dataset " + name);
  if (values.empty()) return;
  std::vector<char> buffer(width * values.size(), '\0');
  for (std::size_t i = 0; i < values.size(); ++i)
    std::copy(values[i].begin(), values[i].end(), buffer.begin() + static_cast<long>(i * width));
  check(H5Dwrite(dset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
        "cannot write dataset " + name);
}

namespace {

/// Creates the groups on the way to `name` that do not exist yet (untimed).
void createParents(hid_t loc, const std::string& name) {
  for (auto slash = name.find('/', 1); slash != std::string::npos;
       slash = name.find('/', slash + 1)) {
    const std::string group = name.substr(0, slash);
    if (!exists(loc, group)) createGroup(loc, group);
  }
}

void createPlain(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type, hid_t space,
                 const void* data) {
  createParents(loc, name);
  Id dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "cannot create property list");
  untimed(dcpl, name);
  Id dset = checked(H5Dcreate2(loc, name.c_str(), file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                    H5Dclose, "cannot create dataset " + name);
  // An empty dataset is created without writing (HDF5 refuses a null buffer).
  if (H5Sget_simple_extent_npoints(space) > 0)
    check(H5Dwrite(dset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "cannot write dataset " + name);
}

/// Dataset `name` opened for reading, or Error("dataset <name> <problem>").
Id openForeign(hid_t file, const std::string& name) {
  if (!exists(file, name)) throw Error("dataset " + name + " is missing");
  return checked(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose,
                 "dataset " + name + " cannot be opened (is it a group?)");
}

}  // namespace

void writePlain(hid_t loc, const std::string& name, Type type, const void* data,
                const std::vector<hsize_t>& dims) {
  Id space =
      checked(dims.empty() ? H5Screate(H5S_SCALAR)
                           : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
              H5Sclose, "cannot create dataspace");
  createPlain(loc, name, fileType(type), memType(type), space, data);
}

void writePlainString(hid_t loc, const std::string& name, const std::string& value) {
  Id type = vlenStringType();
  Id space = checked(H5Screate(H5S_SCALAR), H5Sclose, "cannot create dataspace");
  const char* ptr = value.c_str();
  createPlain(loc, name, type, type, space, &ptr);
}

Array<double> readAnyNumbers(hid_t file, const std::string& name, hsize_t max_values) {
  const std::string D = "dataset " + name + " ";
  Id ds = openForeign(file, name);
  Id type = checked(H5Dget_type(ds), H5Tclose, D + "is not numeric");
  const H5T_class_t cls = H5Tget_class(type);
  if (cls != H5T_INTEGER && cls != H5T_FLOAT) throw Error(D + "is not numeric");
  Id space = checked(H5Dget_space(ds), H5Sclose, D + "has an unreadable shape");
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0) throw Error(D + "has an unreadable shape");
  Array<double> a;
  a.dims.assign(static_cast<std::size_t>(rank), 0);
  if (rank > 0 && H5Sget_simple_extent_dims(space, a.dims.data(), nullptr) < 0)
    throw Error(D + "has an unreadable shape");
  hsize_t count = 1;
  for (hsize_t d : a.dims) {
    if (d != 0 && count > max_values / d)
      throw Error(D + "declares more values than the file holds");
    count *= d;
  }
  if (count > max_values) throw Error(D + "declares more values than the file holds");
  a.values.resize(static_cast<std::size_t>(count));
  if (count > 0)
    check(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()),
          D + "cannot be read as numbers");
  return a;
}

std::string readOneString(hid_t file, const std::string& name) {
  const std::string D = "dataset " + name + " ";
  Id ds = openForeign(file, name);
  Id type = checked(H5Dget_type(ds), H5Tclose, D + "is not a string");
  if (H5Tget_class(type) != H5T_STRING) throw Error(D + "is not a string");
  Id space = checked(H5Dget_space(ds), H5Sclose, D + "should hold one string");
  if (H5Sget_simple_extent_npoints(space) != 1) throw Error(D + "should hold one string");
  const htri_t variable = H5Tis_variable_str(type);
  if (variable < 0) throw Error(D + "cannot be read");
  if (variable > 0) {
    Id mem = checked(H5Tcopy(H5T_C_S1), H5Tclose, D + "cannot be read");
    check(H5Tset_size(mem, H5T_VARIABLE), D + "cannot be read");
    check(H5Tset_cset(mem, H5Tget_cset(type)), D + "cannot be read");  // as stored: no conversion
    char* p = nullptr;
    check(H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p), D + "cannot be read");
    std::string out = p != nullptr ? std::string(p) : std::string();
    if (p != nullptr) H5free_memory(p);
    return out;
  }
  const std::size_t size = H5Tget_size(type);
  if (size > (std::size_t{1} << 20)) throw Error(D + "declares a string longer than 1 MiB");
  std::vector<char> buffer(size + 1, '\0');
  if (size > 0)
    check(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), D + "cannot be read");
  return std::string(buffer.data(), strnlen(buffer.data(), size));
}

bool exists(hid_t loc, const std::string& name) {
  // Check each path component: H5Lexists fails on a missing intermediate group.
  std::string prefix;
  std::size_t start = 0;
  if (!name.empty() && name[0] == '/') {
    prefix = "/";
    start = 1;
  }
  while (start <= name.size()) {
    const std::size_t slash = name.find('/', start);
    const std::string part =
        name.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (part.empty()) break;
    prefix += part;
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) break;
    prefix += "/";
    start = slash + 1;
  }
  return true;
}

bool hasAttr(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

Id openGroup(hid_t file, const std::string& path) {
  if (!exists(file, path)) throw Error("missing group " + path);
  return checked(H5Gopen2(file, path.c_str(), H5P_DEFAULT), H5Gclose,
                 "cannot open group " + path + " (is it a dataset?)");
}

std::string readAttrString(hid_t obj, const std::string& where, const std::string& name) {
  const std::string label = "attribute " + name + " on " + where;
  Id attr = openAttr(obj, where, name);
  Id type = checked(H5Aget_type(attr), H5Tclose, "cannot read the type of " + label);
  if (H5Tget_class(type) != H5T_STRING) throw Error(label + " must be a string");
  if (attrElements(attr, label) != 1) throw Error(label + " must be a single string");
  const htri_t variable = H5Tis_variable_str(type);
  if (variable < 0) throw Error("cannot read the type of " + label);
  if (variable > 0) {
    Id mem = vlenStringType();
    char* p = nullptr;
    check(H5Aread(attr, mem, &p), "cannot read " + label);
    std::string out = p != nullptr ? std::string(p) : std::string();
    if (p != nullptr) H5free_memory(p);
    return out;
  }
  const std::size_t size = H5Tget_size(type);
  if (size == 0 || size > (1u << 24)) throw Error(label + " has an invalid size");
  std::vector<char> buffer(size + 1, '\0');
  check(H5Aread(attr, type, buffer.data()), "cannot read " + label);
  return std::string(buffer.data(), strnlen(buffer.data(), size));
}

double readAttrDouble(hid_t obj, const std::string& where, const std::string& name) {
  return readScalarNumber<double>(obj, where, name, H5T_NATIVE_DOUBLE, true);
}

std::int64_t readAttrInt(hid_t obj, const std::string& where, const std::string& name) {
  return readScalarNumber<std::int64_t>(obj, where, name, H5T_NATIVE_INT64, false);
}

std::uint64_t readAttrUInt(hid_t obj, const std::string& where, const std::string& name) {
  Id attr = openAttr(obj, where, name);
  Id type = checked(H5Aget_type(attr), H5Tclose, "cannot read attribute " + name);
  if (H5Tget_class(type) == H5T_INTEGER && H5Tget_sign(type) == H5T_SGN_2) {
    const std::int64_t v = readAttrInt(obj, where, name);
    if (v < 0) throw Error("attribute " + name + " on " + where + " must not be negative");
    return static_cast<std::uint64_t>(v);
  }
  return readScalarNumber<std::uint64_t>(obj, where, name, H5T_NATIVE_UINT64, false);
}

std::vector<double> readAttrVector(hid_t obj, const std::string& where, const std::string& name,
                                   std::size_t n) {
  const std::string label = "attribute " + name + " on " + where;
  Id attr = openAttr(obj, where, name);
  const H5T_class_t cls = attrClass(attr, label);
  if (cls != H5T_INTEGER && cls != H5T_FLOAT) throw Error(label + " must hold numbers");
  if (attrElements(attr, label) != static_cast<hssize_t>(n))
    throw Error(label + " must hold " + std::to_string(n) + " values");
  std::vector<double> values(n);
  check(H5Aread(attr, H5T_NATIVE_DOUBLE, values.data()), "cannot read " + label);
  return values;
}

std::vector<std::string> attrNames(hid_t obj, const std::string& where) {
  H5O_info_t info;
  check(H5Oget_info(obj, &info), "cannot list the attributes of " + where);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const ssize_t len =
        H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) throw Error("cannot list the attributes of " + where);
    std::vector<char> buffer(static_cast<std::size_t>(len) + 1, '\0');
    if (H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, buffer.data(), buffer.size(),
                           H5P_DEFAULT) < 0)
      throw Error("cannot list the attributes of " + where);
    names.emplace_back(buffer.data());
  }
  return names;
}

Array<double> readF64(hid_t file, const std::string& path, int rank, std::size_t cols) {
  return readArray<double>(file, path, rank, cols, H5T_NATIVE_DOUBLE, true);
}

Array<std::int64_t> readI64(hid_t file, const std::string& path, int rank, std::size_t cols) {
  return readArray<std::int64_t>(file, path, rank, cols, H5T_NATIVE_INT64, false);
}

std::vector<std::string> readStrings(hid_t file, const std::string& path) {
  Opened o = openDataset(file, path, 1, 0);
  if (o.cls != H5T_STRING) throw Error("dataset " + path + " must hold strings");
  Id type = checked(H5Dget_type(o.dataset), H5Tclose, "cannot read the type of " + path);
  std::vector<std::string> out;
  const auto n = static_cast<std::size_t>(o.elements);
  if (n == 0) return out;
  const htri_t variable = H5Tis_variable_str(type);
  if (variable < 0) throw Error("cannot read the type of " + path);
  if (variable > 0) {
    Id mem = vlenStringType();
    std::vector<char*> ptrs(n, nullptr);
    check(H5Dread(o.dataset, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()),
          "cannot read dataset " + path + " (file damaged?)");
    for (char* p : ptrs) {
      out.emplace_back(p != nullptr ? p : "");
      if (p != nullptr) H5free_memory(p);
    }
    return out;
  }
  const std::size_t size = H5Tget_size(type);
  if (size == 0 || size > (1u << 20)) throw Error("dataset " + path + " has an invalid size");
  std::vector<char> buffer(size * n, '\0');
  check(H5Dread(o.dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
        "cannot read dataset " + path + " (file damaged?)");
  for (std::size_t i = 0; i < n; ++i)
    out.emplace_back(buffer.data() + i * size, strnlen(buffer.data() + i * size, size));
  return out;
}

}  // namespace taskmap::h5
