#include "common/h5.hpp"

#include <hdf5.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <unordered_set>
#include <utility>

namespace ricochet::h5 {
namespace {

// HDF5 prints its own error stack to stderr by default; we report errors ourselves.
struct SilenceHdf5 {
  SilenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
const SilenceHdf5 kSilence;

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw std::runtime_error(file + ": HDF5: " + what);
}

// Closes an HDF5 identifier on scope exit whatever its kind.
class Handle {
 public:
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() {
    if (id_ >= 0) H5Oclose_any(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  // Movable so that helpers can return a Handle by name (no NRVO guarantee).
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, -1)) {}
  Handle& operator=(Handle&&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  static void H5Oclose_any(hid_t id) {
    switch (H5Iget_type(id)) {
      case H5I_DATASET: H5Dclose(id); break;
      case H5I_GROUP: H5Gclose(id); break;
      case H5I_DATASPACE: H5Sclose(id); break;
      case H5I_DATATYPE: H5Tclose(id); break;
      case H5I_ATTR: H5Aclose(id); break;
      case H5I_GENPROP_LST: H5Pclose(id); break;
      default: break;
    }
  }
  hid_t id_;
};

Handle link_create_plist() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  return lcpl;
}

Handle vlen_string_type() {
  Handle t(H5Tcopy(H5T_C_S1));
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

// Memory of the variable-length strings HDF5 reads: every block HDF5 allocates is recorded and
// freed when the arena goes out of scope, whether the read succeeded or not.
class VlenArena {
 public:
  VlenArena() = default;
  VlenArena(const VlenArena&) = delete;
  VlenArena& operator=(const VlenArena&) = delete;
  ~VlenArena() {
    for (void* p : blocks_) std::free(p);
  }
  static void* allocate(std::size_t size, void* info) {
    void* p = std::malloc(size);
    if (!p) return nullptr;
    try {
      static_cast<VlenArena*>(info)->blocks_.insert(p);
    } catch (...) {
      std::free(p);
      return nullptr;
    }
    return p;
  }
  static void release(void* p, void* info) {
    if (!p) return;
    static_cast<VlenArena*>(info)->blocks_.erase(p);
    std::free(p);
  }

 private:
  std::unordered_set<void*> blocks_;
};

}  // namespace

bool is_hdf5(const std::string& path) {
  // The signature at offset 0 (HDF5 file format specification, "Format Signature"); files with
  // a user block put it at 512, 1024, ..., which Ricochet never writes.
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic, 8) == "\x89HDF\r\n\x1a\n";
}

File::File(const std::string& path, Mode mode) : path_(path) {
  switch (mode) {
    case Mode::kRead: id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); break;
    case Mode::kTruncate:
      id_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
      break;
    case Mode::kReadWrite: {
#if H5_VERSION_GE(1, 12, 0)
      const htri_t is = H5Fis_accessible(path.c_str(), H5P_DEFAULT);
#else
      // HDF5 1.10 (Debian 12) has no H5Fis_accessible; H5Fis_hdf5 answers the same question.
      const htri_t is = H5Fis_hdf5(path.c_str());
#endif
      id_ = is > 0 ? H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)
                   : H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
      break;
    }
  }
  if (id_ < 0) fail(path, "cannot open file (missing, not HDF5, or not writable)");
}

File::~File() {
  if (id_ >= 0) H5Fclose(id_);
}

File::File(File&& other) noexcept : id_(std::exchange(other.id_, -1)), path_(other.path_) {}

File& File::operator=(File&& other) noexcept {
  if (this != &other) {
    if (id_ >= 0) H5Fclose(id_);
    id_ = std::exchange(other.id_, -1);
    path_ = other.path_;
  }
  return *this;
}

bool File::exists(const std::string& object_path) const {
  // H5Lexists fails on a missing intermediate group, so walk the path.
  std::size_t pos = 1;
  while (pos <= object_path.size()) {
    const auto next = object_path.find('/', pos);
    const std::string prefix = object_path.substr(0, next);
    if (prefix.size() > 1 && H5Lexists(id_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (next == std::string::npos) break;
    pos = next + 1;
  }
  return object_path == "/" || H5Oexists_by_name(id_, object_path.c_str(), H5P_DEFAULT) > 0;
}

std::vector<std::string> File::list(const std::string& group_path) const {
  std::vector<std::string> names;
  Handle group(H5Gopen2(id_, group_path.c_str(), H5P_DEFAULT));
  if (!group.ok()) fail(path_, "no group " + group_path);
  H5G_info_t info;
  if (H5Gget_info(group.get(), &info) < 0) fail(path_, "cannot list group " + group_path);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t n = H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr,
                                         0, H5P_DEFAULT);
    if (n < 0) fail(path_, "cannot list group " + group_path);
    std::string name(static_cast<std::size_t>(n), '\0');
    H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), n + 1,
                       H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

void File::create_group(const std::string& group_path) {
  if (exists(group_path)) return;
  Handle lcpl = link_create_plist();
  Handle g(H5Gcreate2(id_, group_path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!g.ok()) fail(path_, "cannot create group " + group_path);
}

void File::remove(const std::string& object_path) {
  if (exists(object_path)) H5Ldelete(id_, object_path.c_str(), H5P_DEFAULT);
}

void File::write(const std::string& dset_path, std::span<const double> data,
                 std::vector<std::size_t> dims) {
  remove(dset_path);
  if (dims.empty()) dims = {data.size()};
  std::vector<hsize_t> hd(dims.begin(), dims.end());
  Handle space(H5Screate_simple(static_cast<int>(hd.size()), hd.data(), nullptr));
  Handle lcpl = link_create_plist();
  Handle d(H5Dcreate2(id_, dset_path.c_str(), H5T_NATIVE_DOUBLE, space.get(), lcpl.get(),
                      H5P_DEFAULT, H5P_DEFAULT));
  if (!d.ok()) fail(path_, "cannot create dataset " + dset_path);
  if (!data.empty() &&
      H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(path_, "cannot write dataset " + dset_path);
}

void File::write(const std::string& dset_path, std::span<const std::int64_t> data) {
  remove(dset_path);
  hsize_t n = data.size();
  Handle space(H5Screate_simple(1, &n, nullptr));
  Handle lcpl = link_create_plist();
  Handle d(H5Dcreate2(id_, dset_path.c_str(), H5T_NATIVE_INT64, space.get(), lcpl.get(),
                      H5P_DEFAULT, H5P_DEFAULT));
  if (!d.ok()) fail(path_, "cannot create dataset " + dset_path);
  if (n > 0 && H5Dwrite(d.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(path_, "cannot write dataset " + dset_path);
}

void File::write_strings(const std::string& dset_path, const std::vector<std::string>& data) {
  remove(dset_path);
  hsize_t n = data.size();
  std::vector<const char*> ptrs;
  for (const auto& s : data) ptrs.push_back(s.c_str());
  Handle type = vlen_string_type();
  Handle space(H5Screate_simple(1, &n, nullptr));
  Handle lcpl = link_create_plist();
  Handle d(H5Dcreate2(id_, dset_path.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT,
                      H5P_DEFAULT));
  if (!d.ok()) fail(path_, "cannot create dataset " + dset_path);
  if (n > 0 && H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0)
    fail(path_, "cannot write dataset " + dset_path);
}

std::vector<double> File::read_doubles(const std::string& dset_path,
                                       std::vector<std::size_t>* dims) const {
  Handle d(H5Dopen2(id_, dset_path.c_str(), H5P_DEFAULT));
  if (!d.ok()) fail(path_, "no dataset " + dset_path);
  Handle space(H5Dget_space(d.get()));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> hd(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.get(), hd.data(), nullptr);
  std::size_t n = 1;
  for (auto v : hd) n *= v;
  std::vector<double> out(n);
  if (n > 0 && H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(path_, "cannot read " + dset_path + " as numbers");
  if (dims) dims->assign(hd.begin(), hd.end());
  return out;
}

std::vector<std::int64_t> File::read_ints(const std::string& dset_path) const {
  Handle d(H5Dopen2(id_, dset_path.c_str(), H5P_DEFAULT));
  if (!d.ok()) fail(path_, "no dataset " + dset_path);
  Handle space(H5Dget_space(d.get()));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  std::vector<std::int64_t> out(static_cast<std::size_t>(n));
  if (n > 0 && H5Dread(d.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(path_, "cannot read " + dset_path + " as integers");
  return out;
}

std::vector<std::string> File::read_strings(const std::string& dset_path) const {
  Handle d(H5Dopen2(id_, dset_path.c_str(), H5P_DEFAULT));
  if (!d.ok()) fail(path_, "no dataset " + dset_path);
  Handle ftype(H5Dget_type(d.get()));
  if (H5Tget_class(ftype.get()) != H5T_STRING) fail(path_, dset_path + " is not a string dataset");
  Handle space(H5Dget_space(d.get()));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  std::vector<std::string> out;
  if (n <= 0) return out;
  if (H5Tis_variable_str(ftype.get()) > 0) {
    std::vector<char*> ptrs(static_cast<std::size_t>(n), nullptr);
    Handle mtype = vlen_string_type();
    // HDF5 allocates the strings through `arena`, which frees them all afterwards: a read that
    // fails part way on a damaged file loses the strings it had converted inside HDF5 (a leak
    // found by fuzz/fuzz_impact_h5), so H5Dvlen_reclaim on `ptrs` cannot free them.
    VlenArena arena;
    Handle xfer(H5Pcreate(H5P_DATASET_XFER));
    H5Pset_vlen_mem_manager(xfer.get(), VlenArena::allocate, &arena, VlenArena::release, &arena);
    if (H5Dread(d.get(), mtype.get(), H5S_ALL, H5S_ALL, xfer.get(), ptrs.data()) < 0)
      fail(path_, "cannot read " + dset_path);
    for (char* p : ptrs) out.emplace_back(p ? p : "");
  } else {
    const std::size_t width = H5Tget_size(ftype.get());
    std::vector<char> buf(width * static_cast<std::size_t>(n));
    if (H5Dread(d.get(), ftype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0)
      fail(path_, "cannot read " + dset_path);
    for (hssize_t i = 0; i < n; ++i) {
      const char* s = buf.data() + static_cast<std::size_t>(i) * width;
      std::size_t len = 0;
      while (len < width && s[len] != '\0') ++len;
      out.emplace_back(s, len);
    }
  }
  return out;
}

namespace {
Handle open_object_for_attr(hid_t file, const std::string& object_path, const std::string& path) {
  Handle obj(H5Oopen(file, object_path.c_str(), H5P_DEFAULT));
  if (!obj.ok()) fail(path, "no object " + object_path);
  return obj;
}
}  // namespace

void File::set_attr(const std::string& object_path, const std::string& name,
                    const std::string& value) {
  if (!exists(object_path)) create_group(object_path);
  Handle obj = open_object_for_attr(id_, object_path, path_);
  if (H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
  Handle type = vlen_string_type();
  Handle space(H5Screate(H5S_SCALAR));
  Handle a(H5Acreate2(obj.get(), name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  const char* p = value.c_str();
  if (!a.ok() || H5Awrite(a.get(), type.get(), &p) < 0)
    fail(path_, "cannot write attribute " + object_path + "@" + name);
}

void File::set_attr(const std::string& object_path, const std::string& name, double value) {
  if (!exists(object_path)) create_group(object_path);
  Handle obj = open_object_for_attr(id_, object_path, path_);
  if (H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
  Handle space(H5Screate(H5S_SCALAR));
  Handle a(H5Acreate2(obj.get(), name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                      H5P_DEFAULT));
  if (!a.ok() || H5Awrite(a.get(), H5T_NATIVE_DOUBLE, &value) < 0)
    fail(path_, "cannot write attribute " + object_path + "@" + name);
}

bool File::has_attr(const std::string& object_path, const std::string& name) const {
  if (!exists(object_path)) return false;
  Handle obj = open_object_for_attr(id_, object_path, path_);
  return H5Aexists(obj.get(), name.c_str()) > 0;
}

std::string File::attr_string(const std::string& object_path, const std::string& name) const {
  Handle obj = open_object_for_attr(id_, object_path, path_);
  Handle a(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT));
  if (!a.ok()) fail(path_, "no attribute " + object_path + "@" + name);
  Handle ftype(H5Aget_type(a.get()));
  if (H5Tget_class(ftype.get()) != H5T_STRING)
    fail(path_, "attribute " + object_path + "@" + name + " is not a string");
  if (H5Tis_variable_str(ftype.get()) > 0) {
    char* p = nullptr;
    Handle mtype = vlen_string_type();
    if (H5Aread(a.get(), mtype.get(), &p) < 0) {
      if (p) H5free_memory(p);
      fail(path_, "cannot read attribute " + name);
    }
    std::string out = p ? p : "";
    H5free_memory(p);
    return out;
  }
  std::string out(H5Tget_size(ftype.get()), '\0');
  if (H5Aread(a.get(), ftype.get(), out.data()) < 0) fail(path_, "cannot read attribute " + name);
  out.resize(out.find('\0') == std::string::npos ? out.size() : out.find('\0'));
  return out;
}

double File::attr_double(const std::string& object_path, const std::string& name) const {
  Handle obj = open_object_for_attr(id_, object_path, path_);
  Handle a(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT));
  if (!a.ok()) fail(path_, "no attribute " + object_path + "@" + name);
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0)
    fail(path_, "attribute " + object_path + "@" + name + " is not a number");
  return v;
}

std::size_t File::append_rows(const std::string& dset_path, std::span<const double> rows,
                              std::size_t columns) {
  if (columns == 0 || rows.size() % columns != 0)
    fail(path_, "append to " + dset_path + ": row data is not a multiple of the column count");
  const hsize_t add = rows.size() / columns;
  if (!exists(dset_path)) {
    hsize_t dims[2] = {0, columns};
    hsize_t maxdims[2] = {H5S_UNLIMITED, columns};
    Handle space(H5Screate_simple(2, dims, maxdims));
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
    hsize_t chunk[2] = {64, columns};
    H5Pset_chunk(dcpl.get(), 2, chunk);
    Handle lcpl = link_create_plist();
    Handle d(H5Dcreate2(id_, dset_path.c_str(), H5T_NATIVE_DOUBLE, space.get(), lcpl.get(),
                        dcpl.get(), H5P_DEFAULT));
    if (!d.ok()) fail(path_, "cannot create dataset " + dset_path);
  }
  Handle d(H5Dopen2(id_, dset_path.c_str(), H5P_DEFAULT));
  Handle space(H5Dget_space(d.get()));
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2) fail(path_, dset_path + " is not 2-D");
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (dims[1] != columns) fail(path_, dset_path + " has a different column count");
  if (add == 0) return dims[0];
  hsize_t newdims[2] = {dims[0] + add, columns};
  if (H5Dset_extent(d.get(), newdims) < 0) fail(path_, "cannot extend " + dset_path);
  Handle fspace(H5Dget_space(d.get()));
  hsize_t start[2] = {dims[0], 0};
  hsize_t count[2] = {add, columns};
  H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, count, nullptr);
  Handle mspace(H5Screate_simple(2, count, nullptr));
  if (H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, rows.data()) <
      0)
    fail(path_, "cannot append to " + dset_path);
  return newdims[0];
}

std::size_t File::append_strings(const std::string& dset_path,
                                 const std::vector<std::string>& values) {
  Handle type = vlen_string_type();
  if (!exists(dset_path)) {
    hsize_t dims[1] = {0};
    hsize_t maxdims[1] = {H5S_UNLIMITED};
    Handle space(H5Screate_simple(1, dims, maxdims));
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
    hsize_t chunk[1] = {64};
    H5Pset_chunk(dcpl.get(), 1, chunk);
    Handle lcpl = link_create_plist();
    Handle d(H5Dcreate2(id_, dset_path.c_str(), type.get(), space.get(), lcpl.get(), dcpl.get(),
                        H5P_DEFAULT));
    if (!d.ok()) fail(path_, "cannot create dataset " + dset_path);
  }
  Handle d(H5Dopen2(id_, dset_path.c_str(), H5P_DEFAULT));
  Handle space(H5Dget_space(d.get()));
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  const hsize_t add = values.size();
  if (add == 0) return n;
  hsize_t newn = n + add;
  if (H5Dset_extent(d.get(), &newn) < 0) fail(path_, "cannot extend " + dset_path);
  Handle fspace(H5Dget_space(d.get()));
  H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, &n, nullptr, &add, nullptr);
  Handle mspace(H5Screate_simple(1, &add, nullptr));
  std::vector<const char*> ptrs;
  for (const auto& s : values) ptrs.push_back(s.c_str());
  if (H5Dwrite(d.get(), type.get(), mspace.get(), fspace.get(), H5P_DEFAULT, ptrs.data()) < 0)
    fail(path_, "cannot append to " + dset_path);
  return newn;
}

void File::flush() { H5Fflush(id_, H5F_SCOPE_GLOBAL); }

}  // namespace ricochet::h5
