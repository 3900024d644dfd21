// A small RAII layer over the HDF5 C API: the only place in Ricochet that calls H5* directly.
//
// Every command writes its full results (inputs, seeds, model, per-release results, samples,
// indices) through this class. Paths are HDF5 paths ("/calibration/releases/en2"); intermediate
// groups are created on demand. Long runs use append_rows() on an extensible dataset and flush()
// after every row, so a killed run loses nothing already written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ricochet::h5 {

/// Whether `path` is a readable file that starts with the HDF5 signature (a CSV, a missing file
/// or a folder is not). Readers of optional groups (tracks, the impact picture) ask this first,
/// so that a CSV impact set simply has none.
bool is_hdf5(const std::string& path);

class File {
 public:
  enum class Mode { kRead, kReadWrite, kTruncate };
  /// Opens `path`. kReadWrite creates the file when it does not exist. Throws std::runtime_error
  /// naming the file when HDF5 cannot open it.
  File(const std::string& path, Mode mode);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  File(File&& other) noexcept;
  File& operator=(File&& other) noexcept;

  const std::string& path() const { return path_; }
  bool exists(const std::string& object_path) const;
  /// Names of the direct children of a group.
  std::vector<std::string> list(const std::string& group_path) const;
  void create_group(const std::string& group_path);
  /// Removes a dataset or group (no error if absent).
  void remove(const std::string& object_path);

  /// Writes (replacing) a dataset of doubles with shape `dims` (1-D of data.size() if empty).
  void write(const std::string& dset_path, std::span<const double> data,
             std::vector<std::size_t> dims = {});
  void write(const std::string& dset_path, std::span<const std::int64_t> data);
  void write_strings(const std::string& dset_path, const std::vector<std::string>& data);

  std::vector<double> read_doubles(const std::string& dset_path,
                                   std::vector<std::size_t>* dims = nullptr) const;
  std::vector<std::int64_t> read_ints(const std::string& dset_path) const;
  std::vector<std::string> read_strings(const std::string& dset_path) const;

  /// Attributes on a group or dataset (created if the object is a missing group).
  void set_attr(const std::string& object_path, const std::string& name, const std::string& value);
  void set_attr(const std::string& object_path, const std::string& name, double value);
  bool has_attr(const std::string& object_path, const std::string& name) const;
  std::string attr_string(const std::string& object_path, const std::string& name) const;
  double attr_double(const std::string& object_path, const std::string& name) const;

  /// Appends rows to an extensible 2-D dataset of `columns` doubles per row, creating it on first
  /// use. Returns the number of rows after the append. Call flush() to make them durable.
  std::size_t append_rows(const std::string& dset_path, std::span<const double> rows,
                          std::size_t columns);
  /// Appends strings to an extensible 1-D dataset of variable-length strings.
  std::size_t append_strings(const std::string& dset_path, const std::vector<std::string>& values);
  void flush();

 private:
  std::int64_t id_ = -1;
  std::string path_;
};

}  // namespace ricochet::h5
