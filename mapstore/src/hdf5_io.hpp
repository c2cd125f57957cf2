#pragma once
// Private HDF5 helpers of mapstore: RAII handles, typed attributes and datasets. Every function
// throws taskmap::Error with a message naming the HDF5 object; callers add the file name.
// Callers must hold hdf5Mutex() for every HDF5 call (Debian's serial HDF5 is not thread-safe).

#include <hdf5.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace taskmap::h5 {

/// The one lock around every HDF5 call of the process (from mapstore).
std::mutex& hdf5Mutex();

/// Turns off HDF5's automatic error stack printing (call under hdf5Mutex()).
void silenceErrors();

/// Owning HDF5 identifier: closes itself with the matching H5*close function.
class Id {
 public:
  using Closer = herr_t (*)(hid_t);
  Id() = default;
  Id(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  Id(Id&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
  Id& operator=(Id&& other) noexcept;
  ~Id() { reset(); }
  /// Closes now; returns false when closing failed.
  bool reset();
  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }  // NOLINT: used as a plain hid_t in HDF5 calls

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Wraps id, throwing Error(what) when it is negative.
Id checked(hid_t id, Id::Closer closer, const std::string& what);
/// Throws Error(what) when status is negative.
void check(herr_t status, const std::string& what);

/// File access properties of every map this library writes: file-format bounds of HDF5 1.10
/// (superblock, object headers and chunk indexes carry checksums HDF5 verifies).
Id mapFileAccess();
/// File creation properties of every map: a user block of user_block bytes (for the seal; 0
/// for the ACRONYM export), no root-group modification times.
Id mapFileCreation(std::size_t user_block);
/// Opens an HDF5 file image held in memory, read-only, without copying it (core driver).
/// bytes must stay alive and unchanged until the file and every object opened from it are
/// closed. Throws Error(what) when HDF5 cannot open it.
Id openImage(const std::string& bytes, const std::string& what);

// ---- writing ----
/// Creates group name under loc.
Id createGroup(hid_t loc, const std::string& name);
/// Scalar fixed-length UTF-8 string attribute (NUL-padded, at least 1 byte).
void writeAttr(hid_t obj, const std::string& name, const std::string& value);
/// Scalar float64 attribute.
void writeAttr(hid_t obj, const std::string& name, double value);
/// Scalar int64 attribute.
void writeAttrInt(hid_t obj, const std::string& name, std::int64_t value);
/// Scalar uint64 attribute.
void writeAttrUInt(hid_t obj, const std::string& name, std::uint64_t value);
/// Scalar uint8 attribute.
void writeAttrU8(hid_t obj, const std::string& name, std::uint8_t value);
/// 1-D float64 attribute of n values.
void writeAttrVector(hid_t obj, const std::string& name, const double* values, std::size_t n);

/// Element types of stored datasets.
enum class Type { kF64, kI64, kI32, kU8 };

/// Chunked, shuffled, deflated and Fletcher-32 checksummed 2-D dataset of rows x cols, row-major
/// data. Empty datasets (rows or cols 0) are stored contiguous (HDF5 cannot chunk them with a fixed
/// size).
void writeDataset(hid_t loc, const std::string& name, Type type, const void* data, std::size_t rows,
                  std::size_t cols);
/// The same for a 1-D dataset of n values.
void writeVector(hid_t loc, const std::string& name, Type type, const void* data, std::size_t n);
/// 1-D dataset of fixed-length UTF-8 strings (width of the longest, NUL-padded).
void writeStrings(hid_t loc, const std::string& name, const std::vector<std::string>& values);

// ---- writing files of other formats (ACRONYM export) ----
/// Contiguous, unfiltered, untimed dataset `name` (a path relative to loc; missing groups on the
/// way are created untimed) of shape dims (empty: a scalar), row-major data: what h5py writes
/// for `f[name] = array`. An empty dataset is created without writing (data may be null).
void writePlain(hid_t loc, const std::string& name, Type type, const void* data,
                const std::vector<hsize_t>& dims);
/// Scalar variable-length UTF-8 string dataset (h5py's `f[name] = "text"`), placed as writePlain.
void writePlainString(hid_t loc, const std::string& name, const std::string& value);

// ---- reading ----
/// True when loc has a link (group, dataset) of that name.
bool exists(hid_t loc, const std::string& name);
/// True when obj has an attribute of that name.
bool hasAttr(hid_t obj, const std::string& name);
/// Opens group path (absolute) or throws "missing group <path>".
Id openGroup(hid_t file, const std::string& path);
/// Reads a string attribute (variable- or fixed-length). where: e.g. "/object".
std::string readAttrString(hid_t obj, const std::string& where, const std::string& name);
/// Reads a numeric scalar attribute as double (integer or float storage).
double readAttrDouble(hid_t obj, const std::string& where, const std::string& name);
/// Reads an integer scalar attribute.
std::int64_t readAttrInt(hid_t obj, const std::string& where, const std::string& name);
/// Reads an unsigned integer scalar attribute (negative stored values are refused).
std::uint64_t readAttrUInt(hid_t obj, const std::string& where, const std::string& name);
/// Reads a 1-D float attribute of exactly n values.
std::vector<double> readAttrVector(hid_t obj, const std::string& where, const std::string& name,
                                   std::size_t n);
/// Names of all attributes of obj, in creation/name order.
std::vector<std::string> attrNames(hid_t obj, const std::string& where);

/// A dataset read into memory: dims and row-major values converted to T.
template <typename T>
struct Array {
  std::vector<hsize_t> dims;
  std::vector<T> values;
  std::size_t rows() const { return dims.empty() ? 1 : static_cast<std::size_t>(dims[0]); }
};

/// Reads dataset path (absolute), requiring rank (1 or 2) and, when cols > 0, that many columns.
/// Floating T requires float or integer storage; integer T requires integer storage.
Array<double> readF64(hid_t file, const std::string& path, int rank, std::size_t cols = 0);
Array<std::int64_t> readI64(hid_t file, const std::string& path, int rank, std::size_t cols = 0);
/// Reads a 1-D string dataset.
std::vector<std::string> readStrings(hid_t file, const std::string& path);

// ---- reading files of other formats (ACRONYM import) ----
// These throw Error("dataset <name> <problem>"), the problem one of: is missing, cannot be
// opened (is it a group?), is not numeric / is not a string, has an unreadable shape, declares
// more values than the file holds, cannot be read (as numbers), should hold one string,
// declares a string longer than 1 MiB.
/// Dataset `name` of any rank and integer or float type as doubles (dims and row-major values);
/// refuses one that declares more than max_values values before allocating.
Array<double> readAnyNumbers(hid_t file, const std::string& name, hsize_t max_values);
/// The one string of dataset `name` (variable- or fixed-length, at most 1 MiB; a fixed-length
/// string ends at its first NUL).
std::string readOneString(hid_t file, const std::string& name);

}  // namespace taskmap::h5
