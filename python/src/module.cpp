// pmesh: the pm library from Python, in numpy terms (issue 30). Meshes are plain arrays
// (mesh_arrays.h); a ProgressiveMesh holds the library's record, immutable once made, so its
// levels may be extracted from several threads at once; every call that may take long
// releases the GIL. Errors raise pmesh.Error with the library's stable code name.
#include <pybind11/eval.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "errors.h"
#include "mesh_arrays.h"
#include "pm/advanced/pm_stream.h"
#include "pm/encoder.h"
#include "pm/gltf.h"
#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/measured_level.h"
#include "pm/mesh_io.h"
#include "pm/mesh_view.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "pm/surface_distance.h"

namespace pmesh {
namespace {

// The collapse tree, one row per vertex id (ProgressiveMesh.vertex_parents()).
struct VertexParent {
  uint32_t parent;  // the vertex it collapses into (a split's u), or kNoVertex for a root
  uint32_t level;   // the first level that has it: 0 for the base mesh, i + 1 for split i's
};


// ---- files -------------------------------------------------------------------------------

pm::Status read_file(const std::string& path, std::string& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return pm::Status(pm::ErrorCode::kIoError, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return pm::Status(pm::ErrorCode::kIoError, "cannot read");
  bytes = std::move(buffer).str();
  return pm::Status::ok();
}

// A file written through a temporary in the same directory, renamed at the end, so that a
// failure never leaves a partial file at `path` (as the tools do). Destroyed before commit(),
// or after a failed write(), it removes the temporary.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path) : path_(std::move(path)) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() { discard(); }

  bool opened() const { return fd_ >= 0; }
  pm::Status open() {
    temporary_ = path_ + ".tmp.XXXXXX";
    fd_ = mkstemp(temporary_.data());
    if (fd_ < 0) {
      temporary_.clear();
      return error(errno);
    }
    return pm::Status::ok();
  }
  pm::Status write(std::string_view bytes) {
    while (!bytes.empty()) {
      const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return fail(n < 0 ? errno : EIO);
      bytes.remove_prefix(std::size_t(n));
    }
    return pm::Status::ok();
  }
  pm::Status commit() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0 || std::rename(temporary_.c_str(), path_.c_str()) != 0)
      return fail(errno);
    temporary_.clear();
    return pm::Status::ok();
  }

 private:
  static pm::Status error(int number) {
    return pm::Status(pm::ErrorCode::kIoError, std::string("cannot write: ") + std::strerror(number));
  }
  void discard() {
    if (fd_ >= 0) ::close(fd_), fd_ = -1;
    if (!temporary_.empty()) std::remove(temporary_.c_str()), temporary_.clear();
  }
  pm::Status fail(int number) {
    discard();
    return error(number);
  }

  std::string path_, temporary_;
  int fd_ = -1;
};

pm::Status write_file_atomically(const std::string& path, const std::string& bytes) {
  TemporaryFile file(path);
  pm::Status status = file.open();
  if (status) status = file.write(bytes);
  return status ? file.commit() : status;
}

// A mesh file written as pm::write_mesh_to_sink() gives its pieces (a large mesh's text never
// whole in memory), the temporary made at the first piece: a mesh the writer refuses leaves
// nothing.
pm::Status write_mesh_file_atomically(const std::string& path, const pm::Mesh& mesh,
                                      pm::MeshFormat format) {
  TemporaryFile file(path);
  pm::Status status = pm::write_mesh_to_sink(mesh, format, [&](std::string_view piece) {
    pm::Status opened = file.opened() ? pm::Status::ok() : file.open();
    return opened ? file.write(piece) : opened;
  });
  if (status && !file.opened()) status = file.open();  // no piece: an empty file
  return status ? file.commit() : status;
}

// A file's format: pm::MeshFormat's, or glTF (pm/gltf.h: binary .glb, text .gltf).
struct FileFormat {
  pm::MeshFormat mesh = pm::MeshFormat::kUnknown;
  bool gltf = false, glb = false;
};

FileFormat format_for(const std::string& path, const std::optional<std::string>& format) {
  std::string extension = format ? *format : std::filesystem::path(path).extension().string();
  if (!extension.empty() && extension[0] == '.') extension.erase(0, 1);
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  FileFormat f;
  f.gltf = extension == "gltf" || extension == "glb";
  f.glb = extension == "glb";
  f.mesh = pm::mesh_format_from_path("." + extension);
  if (!f.gltf && f.mesh == pm::MeshFormat::kUnknown)
    throw Error(pm::error_code_name(pm::ErrorCode::kUnsupportedFormat),
                path + ": unknown mesh format (use .obj .ply .off .stl .glb .gltf or format=)");
  return f;
}

// ---- read and write ----------------------------------------------------------------------

Mesh read(const std::filesystem::path& file, const std::optional<std::string>& format) {
  const std::string path = file.string();
  const FileFormat f = format_for(path, format);
  pm::Mesh mesh;
  pm::Status status;
  {
    py::gil_scoped_release release;
    std::string bytes;
    status = read_file(path, bytes);
    if (status && f.gltf) {
      pm::GltfReadOptions options;
      options.base_directory = file.parent_path().empty() ? "." : file.parent_path().string();
      status = pm::read_gltf(bytes, options, mesh);
    } else if (status) {
      status = pm::read_mesh_from_memory(bytes, f.mesh, mesh);
    }
  }
  throw_if_failed(status, path);
  return wrap_mesh(std::move(mesh));
}

// glTF levels, coarse to fine, with their error bounds, as one file (pm::write_gltf).
void write_gltf_levels(const std::string& path, const std::vector<const pm::Mesh*>& meshes,
                       const std::vector<double>& errors, bool binary, bool quantize) {
  std::vector<pm::GltfLevel> levels;
  for (std::size_t i = 0; i < meshes.size(); ++i) levels.push_back({meshes[i], errors[i]});
  pm::GltfWriteOptions options;
  options.binary = binary;
  options.quantize = quantize;
  pm::Status status;
  {
    py::gil_scoped_release release;
    std::string bytes;
    status = pm::write_gltf(levels, options, bytes);
    if (status) status = write_file_atomically(path, bytes);
  }
  throw_if_failed(status, path);
}

void write(const std::filesystem::path& file, const Mesh& mesh, const std::optional<std::string>& format) {
  const std::string path = file.string();
  const FileFormat f = format_for(path, format);
  pm::Mesh storage;
  const pm::Mesh& m = library_mesh(mesh, "mesh", storage);
  if (f.gltf) return write_gltf_levels(path, {&m}, {0.0}, f.glb, false);
  pm::Status status;
  {
    py::gil_scoped_release release;
    status = write_mesh_file_atomically(path, m, f.mesh);
  }
  throw_if_failed(status, path);
}

// pmesh.write_gltf: a chain of levels in one glTF file, tied by MSFT_lod.
void write_gltf_chain(const std::filesystem::path& file, const std::vector<Mesh>& meshes,
                      std::optional<std::vector<double>> errors, bool quantize) {
  const std::string path = file.string();
  if (meshes.empty()) invalid_argument("write_gltf: no level");
  if (errors && errors->size() != meshes.size())
    invalid_argument("write_gltf: " + std::to_string(errors->size()) + " errors for " +
                     std::to_string(meshes.size()) + " levels");
  const FileFormat f = format_for(path, std::nullopt);
  if (!f.gltf) invalid_argument(path + ": write_gltf writes .glb or .gltf");
  std::vector<pm::Mesh> storage(meshes.size());
  std::vector<const pm::Mesh*> levels;
  for (std::size_t i = 0; i < meshes.size(); ++i)
    levels.push_back(&library_mesh(meshes[i], ("level " + std::to_string(i)).c_str(), storage[i]));
  write_gltf_levels(path, levels, errors.value_or(std::vector<double>(meshes.size(), 0.0)), f.glb, quantize);
}

Mesh grouped_by_material(const Mesh& mesh) {
  pm::Mesh storage;
  pm::Mesh grouped = library_mesh(mesh, "mesh", storage);
  pm::group_faces_by_material(grouped);
  return wrap_mesh(std::move(grouped));
}

// ---- the progressive mesh ----------------------------------------------------------------

// pmesh.ProgressiveMesh: the library's record, shared and never changed once made.
struct Progressive {
  std::shared_ptr<const pm::ProgressiveMesh> pm;
  pm::WriteOptions write;                     // what to_bytes() writes
  std::shared_ptr<const std::string> stream;  // its bytes, once written
  std::optional<pm::EncodeStats> stats;       // when made by encode()
  std::size_t input_copies = 0;               // input arrays encode() copied for their layout

  std::size_t levels() const { return pm->splits.size() + 1; }
  // Counted once: a walk over every split (0.1 ms on nefertiti's 50k), which level(ratio=)
  // would otherwise add to each call. The GIL guards the cache, as pm never changes.
  std::size_t full_faces() const {
    if (!full_faces_known) full_face_count = pm::faces_at_level(*pm, pm->splits.size());
    full_faces_known = true;
    return full_face_count;
  }
  mutable std::size_t full_face_count = 0;
  mutable bool full_faces_known = false;
  std::size_t checked_level(long long level) const {
    if (level < 0 || std::size_t(level) >= levels())
      invalid_argument("level " + std::to_string(level) + " is not in [0, " +
                       std::to_string(levels() - 1) + "]");
    return std::size_t(level);
  }
};

// A read-only view of one of the record's arrays (rows of `columns`; 0: one value a row), kept
// alive by the Python object that shares the record.
template <class T>
auto record_array(const std::vector<T> pm::ProgressiveMesh::*member, std::size_t columns) {
  return [member, columns](py::object self) {
    const std::vector<T>& values = (*self.cast<const Progressive&>().pm).*member;
    return view(values.data(), columns ? values.size() / columns : values.size(), columns, self, false);
  };
}

// What the levels of one request are chosen by (pmdec's --faces, --vertices, --ratio, --error).
struct Selection {
  std::optional<std::size_t> faces, vertices;
  std::optional<double> ratio, error;
  bool estimate = false;
};

int given(const Selection& s) {
  return int(bool(s.faces)) + int(bool(s.vertices)) + int(bool(s.ratio)) + int(bool(s.error));
}

// The level pmdec selects for the same request: --faces N, --vertices N, --ratio R (faces
// rounded as pmdec rounds them), --error E --absolute (measured, Metro-style, unless
// estimate: the recorded errors).
std::size_t select_level(const Progressive& p, const Selection& s) {
  const pm::ProgressiveMesh& pm = *p.pm;
  if (s.faces) return pm::level_for_faces(pm, *s.faces);
  if (s.vertices) return pm::level_for_vertices(pm, *s.vertices);
  if (s.ratio) {
    if (!(*s.ratio >= 0 && *s.ratio <= 1)) invalid_argument("ratio must be in [0, 1]");
    return pm::level_for_faces(pm, std::size_t(std::llround(*s.ratio * double(p.full_faces()))));
  }
  if (!(*s.error >= 0 && std::isfinite(*s.error)))
    invalid_argument("error must be a finite distance >= 0 (model units)");
  if (s.estimate) return pm::level_for_error(pm, *s.error);
  pm::MeasuredLevel found;
  pm::Status status;
  {
    py::gil_scoped_release release;
    status = pm::level_for_measured_error(pm, *s.error, {}, found);
  }
  throw_if_failed(status);
  return found.level;
}

std::size_t level_index(const Progressive& p, std::optional<long long> level, const Selection& s) {
  const int count = given(s) + int(bool(level));
  if (count != 1)
    invalid_argument("give exactly one of level, faces=, vertices=, ratio=, error= (got " +
                     std::to_string(count) + ")");
  if (s.estimate && !s.error) invalid_argument("estimate= goes with error=");
  return level ? p.checked_level(*level) : select_level(p, s);
}

Mesh extract(const Progressive& p, std::size_t level) {
  pm::Mesh mesh;
  {
    py::gil_scoped_release release;
    mesh = pm::extract_level(*p.pm, level);
  }
  return wrap_mesh(std::move(mesh));
}

std::vector<Mesh> extract_many(const Progressive& p, std::optional<std::vector<long long>> levels,
                               std::optional<std::vector<std::size_t>> faces,
                               std::optional<std::vector<std::size_t>> vertices,
                               std::optional<std::vector<double>> ratio) {
  const int count = int(bool(levels)) + int(bool(faces)) + int(bool(vertices)) + int(bool(ratio));
  if (count != 1) invalid_argument("give exactly one list: levels, faces=, vertices= or ratio=");
  std::vector<std::size_t> chosen;
  if (levels)
    for (long long level : *levels) chosen.push_back(p.checked_level(level));
  if (faces)
    for (std::size_t n : *faces) chosen.push_back(select_level(p, Selection{n, {}, {}, {}}));
  if (vertices)
    for (std::size_t n : *vertices) chosen.push_back(select_level(p, Selection{{}, n, {}, {}}));
  if (ratio)
    for (double r : *ratio) chosen.push_back(select_level(p, Selection{{}, {}, r, {}}));
  // One walk over the splits (pm::extract_levels); each distinct level once, given to every
  // request for it.
  std::vector<pm::Mesh> meshes(chosen.size());
  {
    py::gil_scoped_release release;
    pm::extract_levels(*p.pm, chosen, [&](std::size_t level, const pm::Mesh& mesh) {
      for (std::size_t i = 0; i < chosen.size(); ++i)
        if (chosen[i] == level) meshes[i] = mesh;
    });
  }
  std::vector<Mesh> out;
  for (pm::Mesh& mesh : meshes) out.push_back(wrap_mesh(std::move(mesh)));
  return out;
}

const std::string& stream_of(Progressive& p) {
  if (!p.stream) {
    auto bytes = std::make_shared<std::string>();
    pm::Status status;
    {
      py::gil_scoped_release release;
      status = pm::write_pm(*p.pm, p.write, *bytes);
    }
    throw_if_failed(status);
    p.stream = std::move(bytes);
  }
  return *p.stream;
}

Progressive decode_stream(std::string_view bytes, uint64_t max_memory, bool allow_truncated,
                          const std::string& where) {
  pm::ReadOptions options;
  options.max_memory = max_memory;
  options.allow_truncated = allow_truncated;
  auto pm = std::make_shared<pm::ProgressiveMesh>();
  pm::Status status;
  {
    py::gil_scoped_release release;
    status = pm::read_pm(bytes, *pm, options);
  }
  throw_if_failed(status, where);
  Progressive p;
  p.pm = std::move(pm);
  return p;
}

// ---- encode ------------------------------------------------------------------------------

// A Python progress callback called from the encoder's thread: with the GIL taken for the
// call only. An exception it raises is kept and raised once encode() returns (the encoder
// cannot be stopped half way).
struct ProgressCallback {
  py::object function;
  std::exception_ptr failure;
  void operator()(double fraction) {
    py::gil_scoped_acquire acquire;
    if (failure) return;
    try {
      function(fraction);
    } catch (...) {
      failure = std::current_exception();
    }
  }
};

void check_bits(int bits, const char* name) {
  if (bits != 0 && (bits < 4 || bits > 24)) invalid_argument(std::string(name) + " must be 0 or 4..24");
}


// encode()'s arguments beyond the mesh, as pmenc's options (README.md, "Use"): the library's
// option structs, filled by the binding, and the choices pmenc derives them from.
struct EncodeArguments {
  pm::EncodeOptions encode;
  pm::WriteOptions write;
  std::string metric = "quadric";
  std::optional<int> error_bits;  // default: kQuantizedErrorBits with quantized positions
  std::size_t fast_from = pm::kDefaultFastFrom;
  std::optional<double> feature_angle;
  bool layered = false;
  py::object progress = py::none();
};

// Checks the arguments (raises on one out of range) and completes the options as pmenc does.
void complete_options(EncodeArguments& a) {
  pm::EncodeOptions& encode = a.encode;
  pm::WriteOptions& write = a.write;
  if (a.metric == "quadric") encode.metric = pm::Metric::kQuadric;
  else if (a.metric == "schroeder") encode.metric = pm::Metric::kSchroeder;
  else invalid_argument("metric must be 'quadric' or 'schroeder', not '" + a.metric + "'");
  check_bits(write.position_bits, "quantize");
  check_bits(write.uv_bits, "quantize_uv");
  check_bits(write.normal_bits, "quantize_normal");
  if (a.error_bits && (*a.error_bits < 0 || *a.error_bits > 24)) invalid_argument("error_bits must be in 0..24");
  if (write.zstd_level < 1 || write.zstd_level > 22) invalid_argument("zstd_level must be in 1..22");
  if (write.chunk_splits < 1 || write.chunk_splits > (1u << 20)) invalid_argument("chunk_splits must be in 1..2^20");
  if (!(encode.layer_window >= 0 && encode.layer_window <= 1)) invalid_argument("layer_window must be in [0, 1]");
  if (a.feature_angle && !(*a.feature_angle >= 0 && *a.feature_angle <= 180))
    invalid_argument("feature_angle must be in [0, 180] degrees");
  if (!(encode.max_normal_flip_deg >= 0 && encode.max_normal_flip_deg <= 180))
    invalid_argument("max_normal_flip must be in [0, 180] degrees");
  if (!a.progress.is_none() && !PyCallable_Check(a.progress.ptr()))
    invalid_argument("progress must be callable");
  encode.feature_angle_deg = a.feature_angle.value_or(-1);  // negative: the metric's default
  encode.fast_from = a.fast_from;  // pmenc's --fast-from: pm::encode applies it
  if (a.layered) encode.layer_window = std::numeric_limits<double>::infinity();
  write.error_bits = a.error_bits.value_or(write.position_bits > 0 ? pm::kQuantizedErrorBits : 0);
  write.threads = encode.threads;
}

Progressive encode(const Mesh& mesh, EncodeArguments arguments) {
  // The caller's arrays go to the library as views (no copy here); encode() gathers them
  // once, at its start, and checks what it gathered, so that an array another thread writes
  // meanwhile gives an error or the new values, never a crash.
  LibraryInput input;
  library_input(mesh, "input", input);
  complete_options(arguments);
  pm::EncodeOptions& options = arguments.encode;
  Progressive p;
  p.write = arguments.write;
  // Only a pointer goes into the options: they may be copied on the encoder's threads,
  // where a Python object may not be.
  ProgressCallback callback{arguments.progress, nullptr};
  if (!arguments.progress.is_none()) options.progress = [&callback](double f) { callback(f); };
  const bool lossy = p.write.position_bits || p.write.uv_bits || p.write.normal_bits || p.write.error_bits;
  auto encoded = std::make_shared<pm::ProgressiveMesh>();
  pm::EncodeStats stats;
  pm::Status status;
  std::shared_ptr<std::string> stream;
  {
    py::gil_scoped_release release;
    // The splits' windows stay inside the chunks of the stream p.write writes.
    status = input.mesh ? pm::encode(*input.mesh, options, p.write, *encoded, &stats)
                        : pm::encode(input.view, options, p.write, *encoded, &stats);
    // Lossy storage (grids, error bits) changes the levels: the object holds what a reader
    // of its stream decodes, the levels pmdec gives for pmenc's file.
    if (status && lossy) {
      stream = std::make_shared<std::string>();
      status = pm::write_pm(*encoded, p.write, *stream);
      if (status) {
        auto decoded = std::make_shared<pm::ProgressiveMesh>();
        status = pm::read_pm(*stream, *decoded);
        encoded = std::move(decoded);
      }
    }
  }
  if (callback.failure) std::rethrow_exception(callback.failure);
  throw_if_failed(status, "encode");
  p.pm = std::move(encoded);
  p.stream = std::move(stream);
  p.stats = stats;
  p.input_copies = input.copied_arrays;
  return p;
}

// ---- runtime -----------------------------------------------------------------------------

// pmesh.Runtime: a pm::RuntimeLod on the heap, never moved, so that the geomorphs made from
// it (which refer to it) stay valid; each geomorph shares its ownership.
struct Runtime {
  std::shared_ptr<pm::RuntimeLod> lod;
};

struct Geomorph {
  std::shared_ptr<pm::RuntimeLod> lod;
  pm::RuntimeLod::Geomorph morph;
  std::size_t from = 0, to = 0;
};

float checked_alpha(double alpha) {
  if (!(alpha >= 0 && alpha <= 1)) invalid_argument("alpha must be in [0, 1]");
  return float(alpha);
}

// ---- surface distance --------------------------------------------------------------------

struct Distance {
  pm::SurfaceDistance d;
  std::size_t faces = 0;  // of the mesh measured against the reference
  std::optional<double> percent(double value) const {
    if (!(d.diagonal > 0)) return std::nullopt;
    return 100 * value / d.diagonal;
  }
};

Distance surface_distance(const Mesh& reference, const Mesh& other, double samples_per_face,
                          uint64_t seed, unsigned threads) {
  if (!(samples_per_face >= 1 && std::isfinite(samples_per_face)))
    invalid_argument("samples_per_face must be a finite number >= 1");
  pm::Mesh reference_storage, other_storage;
  const pm::Mesh& a = library_mesh(reference, "reference", reference_storage);
  const pm::Mesh& b = library_mesh(other, "other", other_storage);
  pm::DistanceOptions options;
  options.samples_per_face = samples_per_face;
  options.seed = seed;
  options.threads = threads;
  Distance out;
  out.faces = b.face_count();
  pm::Status status;
  {
    py::gil_scoped_release release;
    status = pm::measure_surface_distance(a, b, options, out.d);
  }
  throw_if_failed(status, "surface_distance");
  return out;
}

// pmdec --compare's line: "hausdorff H (P% of diagonal) rms R (Q%) faces F samples S".
std::string distance_text(const Distance& distance) {
  const pm::SurfaceDistance& d = distance.d;
  char percents[2][32] = {"n/a", "n/a"};
  if (d.diagonal > 0) {
    std::snprintf(percents[0], sizeof percents[0], "%.3g%%", 100 * d.hausdorff / d.diagonal);
    std::snprintf(percents[1], sizeof percents[1], "%.3g%%", 100 * d.rms / d.diagonal);
  }
  char text[256];
  std::snprintf(text, sizeof text, "hausdorff %.6g (%s of diagonal) rms %.6g (%s) faces %zu samples %zu",
                d.hausdorff, percents[0], d.rms, percents[1], distance.faces, d.samples);
  return text;
}

// ---- the Python error class --------------------------------------------------------------

PyObject* error_type = nullptr;

void define_error(py::module_& m) {
  py::dict scope;
  scope["__name__"] = "pmesh";
  py::exec(R"(
class Error(Exception):
    """A pm library error: `code` is its stable name ('parse-error', 'io-error',
    'invalid-argument', 'corrupt-stream', 'truncated-stream', 'checksum-mismatch',
    'unsupported-format', 'unsupported-version', 'empty-mesh', 'resource-limit',
    'internal'), `message` one line naming the file or argument and the problem."""

    def __init__(self, code, message):
        super().__init__(code, message)
        self.code = code
        self.message = message

    def __str__(self):
        return f"{self.message} [{self.code}]"
)",
           scope);
  py::object error = scope["Error"];
  error_type = error.inc_ref().ptr();
  m.attr("Error") = error;
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const Error& e) {
      PyErr_SetObject(error_type, py::make_tuple(e.code(), e.message()).ptr());
    }
  });
}

}  // namespace
}  // namespace pmesh

namespace py = pybind11;
using pmesh::Distance;
using pmesh::EncodeArguments;
using pmesh::Geomorph;
using pmesh::Mesh;
using pmesh::Progressive;
using pmesh::Runtime;
using pmesh::Selection;

PYBIND11_MODULE(pmesh, m) {
  m.doc() = R"(Progressive meshes (Hoppe 1996) from numpy: encode a triangle mesh once, then take
any level of detail, several in one walk, a runtime that refines and coarsens in place,
geomorphs, and measured distances. The pm library (C++) does the work; see README.md,
"Python".

    import pmesh
    mesh = pmesh.read("bunny.obj")               # positions (n, 3) float32, faces (m, 3) uint32
    pm = pmesh.encode(mesh)                      # or encode(positions, faces, ...)
    low = pm.level(ratio=0.1)                    # a pmesh.Mesh
    pmesh.write("bunny_10.obj", low)
    print(pmesh.surface_distance(mesh, low))     # as pmdec --compare prints it

Errors raise pmesh.Error; its `code` is the library's stable name. Calls that may take long
release the GIL, so threads encode or extract in parallel.)";
  m.attr("__version__") = PM_VERSION_STRING;
  m.attr("FORMAT_VERSION") = py::make_tuple(pm::kFormatMajor, pm::kFormatMinor);
  m.attr("NO_ATTRIBUTE") = pm::kNoAttribute;
  m.attr("NO_VERTEX") = pm::kNoVertex;
  pmesh::define_error(m);
  pmesh::register_mesh(m);
  // splits() is a view of the library's records: the dtype is VertexSplit's layout.
  PYBIND11_NUMPY_DTYPE(pm::VertexSplit, u, vl, vr, error, moved_begin, moved_count);
  PYBIND11_NUMPY_DTYPE(pmesh::VertexParent, parent, level);

  // ---- read / write ----
  m.def("read", &pmesh::read, py::arg("path"), py::arg("format") = py::none(),
        R"(Reads a mesh file: OBJ, PLY, OFF, STL, glTF (.glb, .gltf: the default scene's triangles,
transforms applied) by extension, or format='obj'|'ply'|'off'|'stl'|'glb'|'gltf',
with every attribute the file holds (README.md, "Input and output formats"). Polygons are
split into triangle fans. Returns a pmesh.Mesh. Raises pmesh.Error: io-error, parse-error
(the message names the line or element), unsupported-format, empty-mesh.)");
  m.def("write", &pmesh::write, py::arg("path"), py::arg("mesh"), py::arg("format") = py::none(),
        R"(Writes a mesh with every attribute the format can hold: OBJ and OFF as text (float32
values in their shortest form that reads back to the same bits), PLY binary little-endian, STL
binary (geometry only), glTF (.glb, .gltf: one node); by extension or format=. The file
appears complete or not at all (a temporary renamed). The bytes are those pmdec writes for
the same mesh.)");
  m.def("write_gltf", &pmesh::write_gltf_chain, py::arg("path"), py::arg("levels"),
        py::arg("errors") = py::none(), py::kw_only(), py::arg("quantize") = false,
        R"(Writes levels (meshes, coarse to fine, e.g. ProgressiveMesh.levels(...)) as ONE glTF file
(.glb or .gltf): one vertex buffer the levels share, one node per level tied by MSFT_lod,
screen-coverage hints from `errors` (each level's error bound, model units, as error_at gives
them). quantize: KHR_mesh_quantization. README.md, "glTF".)");
  m.def("group_faces_by_material", &pmesh::grouped_by_material, py::arg("mesh"),
        R"(A copy of the mesh with each material's faces contiguous (stable; materials in the order
of their first face), as pmdec writes levels: one usemtl per material in an OBJ. Without
materials, the same faces.)");

  // ---- the progressive mesh ----
  py::class_<Progressive>(m, "ProgressiveMesh", R"(A progressive mesh: a base mesh and the vertex
splits that refine it back to the input (Hoppe 1996, §3). Level k is the base mesh refined by
the first k splits; len(pm) levels, from 0 (the base mesh) to len(pm) - 1 (the input,
exactly). Immutable: levels may be taken from several threads at once.)")
      .def("__len__", &Progressive::levels, "The number of levels: splits + 1.")
      .def_property_readonly("split_count", [](const Progressive& p) { return p.pm->splits.size(); })
      .def_property_readonly("base_vertex_count", [](const Progressive& p) { return p.pm->base_vertex_count; })
      .def_property_readonly("vertex_count", [](const Progressive& p) { return p.pm->vertex_count(); },
                             "Vertex ids of every level (rows of positions).")
      .def_property_readonly("full_faces", &Progressive::full_faces, "Faces at full detail.")
      .def_property_readonly("keeps_order", [](const Progressive& p) { return p.pm->keeps_order(); })
      .def_property_readonly(
          "stats",
          [](const Progressive& p) -> py::object {
            if (!p.stats) return py::none();
            const pm::EncodeStats& s = *p.stats;
            py::dict repair;
            repair["vertices_duplicated"] = s.repair.vertices_duplicated;
            repair["complex_edges"] = s.repair.complex_edges;
            repair["carried_faces"] = s.repair.carried_faces;
            repair["loose_vertices"] = s.repair.loose_vertices;
            py::dict d;
            d["input_faces"] = s.input_faces;
            d["base_faces"] = s.base_faces;
            d["base_vertices"] = s.base_vertices;
            d["splits"] = s.collapses;
            d["loop"] = s.fast ? "fast" : "default";  // as pmenc's --json
            d["repair"] = repair;
            d["input_copies"] = p.input_copies;
            return std::move(d);
          },
          R"(What encode() did (as pmenc --json reports it), or None for a decoded mesh; and
input_copies: how many input arrays were copied before the library read them (0 when every
array was read in place: see encode()).)")
      .def(
          "level_for",
          [](const Progressive& p, std::optional<std::size_t> faces, std::optional<std::size_t> vertices,
             std::optional<double> ratio, std::optional<double> error, bool estimate) {
            return pmesh::level_index(p, std::nullopt, Selection{faces, vertices, ratio, error, estimate});
          },
          py::kw_only(), py::arg("faces") = py::none(), py::arg("vertices") = py::none(),
          py::arg("ratio") = py::none(), py::arg("error") = py::none(), py::arg("estimate") = false,
          R"(The level pmdec selects: faces=N (the coarsest level with at least N faces),
vertices=N, ratio=R (of the full faces, rounded), error=E (model units: the coarsest level
whose measured Hausdorff distance to full detail is at most E, as pmdec --error E --absolute;
with estimate=True, by the errors recorded in the stream instead, instantly).)")
      .def(
          "level",
          [](const Progressive& p, std::optional<long long> level, std::optional<std::size_t> faces,
             std::optional<std::size_t> vertices, std::optional<double> ratio, std::optional<double> error,
             bool estimate) {
            return pmesh::extract(p, pmesh::level_index(p, level, Selection{faces, vertices, ratio, error, estimate}));
          },
          py::arg("level") = py::none(), py::kw_only(), py::arg("faces") = py::none(),
          py::arg("vertices") = py::none(), py::arg("ratio") = py::none(), py::arg("error") = py::none(),
          py::arg("estimate") = false,
          R"(The mesh of one level: by index, or faces=, vertices=, ratio=, error= as level_for().
Welded copies are merged back and unused vertices dropped; its arrays are the library's
(no copy). The same mesh as pmdec writes for the same option.)")
      .def("levels", &pmesh::extract_many, py::arg("levels") = py::none(), py::kw_only(),
           py::arg("faces") = py::none(), py::arg("vertices") = py::none(), py::arg("ratio") = py::none(),
           R"(Several levels in one walk over the splits (pmdec --lods): a list of level indices,
or faces=[...], vertices=[...], ratio=[...]. Returns the meshes in the order asked.)")
      .def("error_at", [](const Progressive& p, long long level) {
             return pm::error_at_level(*p.pm, p.checked_level(level));
           }, py::arg("level"), "The recorded error bound of a level (model units; 0 at full detail).")
      .def("faces_at", [](const Progressive& p, long long level) {
             return pm::faces_at_level(*p.pm, p.checked_level(level));
           }, py::arg("level"), "Faces output at a level.")
      .def("vertices_at", [](const Progressive& p, long long level) {
             return pm::vertices_at_level(*p.pm, p.checked_level(level));
           }, py::arg("level"), "Vertices output at a level (welded copies not counted).")
      .def_property_readonly(
          "positions", pmesh::record_array(&pm::ProgressiveMesh::positions, 3),
          "(vertex_count, 3) float32, read-only: every vertex id's position (base vertices, then "
          "one per split, then loose vertices).")
      .def_property_readonly(
          "base_faces", pmesh::record_array(&pm::ProgressiveMesh::base_faces, 3),
          "(b, 3) uint32, read-only: the base mesh's faces, as vertex ids.")
      .def_property_readonly(
          "moved_faces", pmesh::record_array(&pm::ProgressiveMesh::moved_faces, 0),
          "uint32, read-only: the splits' moved face ids, back to back (splits()['moved_begin'], "
          "['moved_count']).")
      .def(
          "splits", pmesh::record_array(&pm::ProgressiveMesh::splits, 0),
          R"(The vertex splits, coarse to fine, as a read-only structured array over the library's
records (no copy): u, vl, vr (uint32; vl or vr NO_VERTEX on a boundary), error (float32, the
bound before the split), moved_begin, moved_count (into moved_faces). Split i creates vertex
base_vertex_count + i from u, turns the moved faces' corner u into it, and appends the faces
(v, u, vl) then (u, v, vr) where vl, vr exist (Hoppe 1996, §3).)")
      .def(
          "vertex_parents",
          [](const Progressive& p) {
            const pm::ProgressiveMesh& pm = *p.pm;
            py::array_t<pmesh::VertexParent> out(py::ssize_t(pm.vertex_count()));
            auto* rows = out.mutable_data();
            const std::size_t base = pm.base_vertex_count, splits = pm.splits.size();
            for (std::size_t v = 0; v < pm.vertex_count(); ++v) {
              const bool split = v >= base && v - base < splits;
              rows[v].parent = split ? pm.splits[v - base].u : pm::kNoVertex;
              rows[v].level = uint32_t(v < base ? 0 : split ? v - base + 1 : splits);
            }
            return out;
          },
          R"(The collapse tree: for each vertex id, a structured row of parent (uint32: the vertex
it collapses into, the u of the split that creates it; NO_VERTEX for base and loose vertices)
and level (uint32: the first level that has it). A new array.)")
      .def(
          "to_bytes",
          [](Progressive& p) {
            const std::string& bytes = pmesh::stream_of(p);
            return py::bytes(bytes.data(), bytes.size());
          },
          R"(The .pm stream (formats/pm-format.md), as pmenc writes it with the same options:
encode()'s quantize=, zstd_level=, ... ; lossless for a decoded mesh.)")
      .def(
          "save",
          [](Progressive& p, const std::filesystem::path& file) {
            const std::string path = file.string();
            const std::string& bytes = pmesh::stream_of(p);
            pm::Status status;
            {
              py::gil_scoped_release release;
              status = pmesh::write_file_atomically(path, bytes);
            }
            pmesh::throw_if_failed(status, path);
          },
          py::arg("path"), "Writes to_bytes() to a file (complete or not at all).")
      .def(
          "runtime",
          [](const Progressive& p) {
            std::shared_ptr<pm::RuntimeLod> lod;
            {
              py::gil_scoped_release release;
              lod = std::make_shared<pm::RuntimeLod>(*p.pm);
            }
            return Runtime{std::move(lod)};
          },
          "A pmesh.Runtime at level 0 (Hoppe 1998's layout: refine and coarsen in place).")
      .def("__repr__", [](const Progressive& p) {
        return "pmesh.ProgressiveMesh(" + std::to_string(p.levels()) + " levels, " +
               std::to_string(pm::faces_at_level(*p.pm, 0)) + " to " + std::to_string(p.full_faces()) +
               " faces)";
      });

  // ---- encode / decode ----
  m.def(
      "encode",
      [](py::object mesh_or_positions, py::object faces, py::object uvs, py::object uv_indices,
         py::object normals, py::object normal_indices, py::object colors, py::object face_materials,
         py::list material_names, py::list material_libraries, std::string metric, int quantize,
         int quantize_uv, int quantize_normal, std::optional<int> error_bits, bool fast,
         std::size_t fast_from, std::optional<double> feature_angle, double max_normal_flip,
         bool keep_corners, bool keep_order, bool drop_attributes, std::size_t min_faces,
         std::size_t min_vertices, double layer_window, bool layered, uint32_t chunk_splits,
         int zstd_level, unsigned threads, py::object progress) {
        Mesh mesh;
        if (py::isinstance<Mesh>(mesh_or_positions)) {
          if (!faces.is_none() || !uvs.is_none() || !uv_indices.is_none() || !normals.is_none() ||
              !normal_indices.is_none() || !colors.is_none() || !face_materials.is_none() ||
              material_names.size() || material_libraries.size())
            pmesh::invalid_argument("encode: give a Mesh or arrays, not both");
          mesh = mesh_or_positions.cast<Mesh>();
        } else {
          mesh.positions = mesh_or_positions;
          mesh.faces = faces;
          mesh.uvs = uvs;
          mesh.uv_indices = uv_indices;
          mesh.normals = normals;
          mesh.normal_indices = normal_indices;
          mesh.colors = colors;
          mesh.face_materials = face_materials;
          mesh.material_names = material_names;
          mesh.material_libraries = material_libraries;
        }
        EncodeArguments a;
        a.metric = metric;
        a.write.position_bits = quantize;
        a.write.uv_bits = quantize_uv;
        a.write.normal_bits = quantize_normal;
        a.error_bits = error_bits;
        a.encode.fast = fast;
        a.fast_from = fast_from;
        a.feature_angle = feature_angle;
        a.encode.max_normal_flip_deg = max_normal_flip;
        a.encode.keep_corners = keep_corners;
        a.encode.keep_order = keep_order;
        a.encode.drop_attributes = drop_attributes;
        a.encode.min_faces = min_faces;
        a.encode.min_vertices = min_vertices;
        a.encode.layer_window = layer_window;
        a.layered = layered;
        a.write.chunk_splits = chunk_splits;
        a.write.zstd_level = zstd_level;
        a.encode.threads = threads;
        a.progress = progress;
        return pmesh::encode(mesh, a);
      },
      py::arg("mesh_or_positions"), py::arg("faces") = py::none(), py::kw_only(),
      py::arg("uvs") = py::none(), py::arg("uv_indices") = py::none(), py::arg("normals") = py::none(),
      py::arg("normal_indices") = py::none(), py::arg("colors") = py::none(),
      py::arg("face_materials") = py::none(), py::arg("material_names") = py::list(),
      py::arg("material_libraries") = py::list(), py::arg("metric") = "quadric",
      py::arg("quantize") = 0, py::arg("quantize_uv") = 0, py::arg("quantize_normal") = 0,
      py::arg("error_bits") = py::none(), py::arg("fast") = false, py::arg("fast_from") = pm::kDefaultFastFrom,
      py::arg("feature_angle") = py::none(), py::arg("max_normal_flip") = 90.0,
      py::arg("keep_corners") = false, py::arg("keep_order") = false, py::arg("drop_attributes") = false,
      py::arg("min_faces") = 0, py::arg("min_vertices") = 0, py::arg("layer_window") = 1.0 / 16,
      py::arg("layered") = false, py::arg("chunk_splits") = pm::WriteOptions{}.chunk_splits,
      py::arg("zstd_level") = pm::WriteOptions{}.zstd_level,
      py::arg("threads") = 0, py::arg("progress") = py::none(),
      R"(Encodes a mesh as a ProgressiveMesh, as pmenc does with the same options: a pmesh.Mesh,
or positions (n, 3) float32 and faces (m, 3) uint32 with the Mesh's optional attribute arrays.

metric 'quadric' (Garland and Heckbert 1997) or 'schroeder'; quantize, quantize_uv,
quantize_normal: 0 (lossless) or 4..24 bits; error_bits (default 5 with quantize, else 0);
fast (the collapse loop without its measured distance: faster, levels about meshoptimizer's),
fast_from (meshes of at least this many faces take it: 0 only with fast); feature_angle (degrees; None: the metric's default), max_normal_flip,
keep_corners, keep_order, drop_attributes, min_faces, min_vertices, layer_window, layered,
chunk_splits, zstd_level, threads (0: every core); progress: a callable given the fraction
done now and then. With a lossy option, the result holds what its stream decodes to, the
levels pmdec gives for pmenc's file. The inputs are checked first (pmesh.Error,
invalid-argument, naming the array and row); the GIL is released while encoding.
The binding makes no copy of the arrays: the library reads them through views (pm/mesh_view.h;
it gathers them once into its encoder's input, as it reads a Mesh) when each row's values are packed, as in a C-contiguous array or a column slice of a wider
one (rows a stride apart); an array of another layout (Fortran order, rows backwards) is
copied first (stats['input_copies'] counts them). A Mesh the library made goes in as it is.)");
  m.def(
      "decode",
      [](py::buffer data, uint64_t max_memory, bool allow_truncated) {
        py::buffer_info info = data.request();
        if (info.itemsize != 1 || info.ndim != 1 || info.strides[0] != 1)
          pmesh::invalid_argument("decode: expected bytes (a contiguous buffer of bytes)");
        const std::string_view bytes(static_cast<const char*>(info.ptr),
                                     std::size_t(info.size * info.itemsize));
        return pmesh::decode_stream(bytes, max_memory, allow_truncated, "decode");
      },
      py::arg("data"), py::kw_only(), py::arg("max_memory") = 0, py::arg("allow_truncated") = false,
      R"(A ProgressiveMesh from a .pm stream (bytes, bytearray, memoryview: read in place).
max_memory: refuse a stream whose decoding needs more bytes (resource-limit); allow_truncated:
a stream cut short decodes to the finest level it holds. Raises pmesh.Error:
truncated-stream, corrupt-stream, checksum-mismatch, unsupported-version, resource-limit.)");
  m.def(
      "load",
      [](const std::filesystem::path& file, uint64_t max_memory, bool allow_truncated) {
        const std::string path = file.string();
        std::string bytes;
        pm::Status status;
        {
          py::gil_scoped_release release;
          status = pmesh::read_file(path, bytes);
        }
        pmesh::throw_if_failed(status, path);
        return pmesh::decode_stream(bytes, max_memory, allow_truncated, path);
      },
      py::arg("path"), py::kw_only(), py::arg("max_memory") = 0, py::arg("allow_truncated") = false,
      "A ProgressiveMesh from a .pm file (as decode()).");

  // ---- runtime ----
  py::class_<Runtime>(m, "Runtime", R"(Levels of detail at run time (Hoppe 1998, "Efficient
implementation of progressive meshes"): render vertices are wedges stored once for every
level, faces in the order they appear, so the active faces are a prefix of the index buffer.
set_level / set_faces / set_vertices / set_error apply only the splits or collapses between
the current level and the requested one, each rewriting one corner per face it moves.
indices, positions, uvs, normals, colors are read-only views of the runtime's own buffers
(no copy): indices changes in place as the level changes; take it again for the new count.)")
      .def_property_readonly("level", [](const Runtime& r) { return r.lod->level(); })
      .def_property_readonly("max_level", [](const Runtime& r) { return r.lod->max_level(); })
      .def_property_readonly("face_count", [](const Runtime& r) { return r.lod->face_count(); })
      .def_property_readonly("vertex_count", [](const Runtime& r) { return r.lod->vertex_count(); })
      .def_property_readonly("wedge_count", [](const Runtime& r) { return r.lod->wedge_count(); })
      .def("set_level", [](Runtime& r, std::size_t level) {
             if (level > r.lod->max_level()) pmesh::invalid_argument("level beyond max_level");
             r.lod->set_level(level);
             return r.lod->level();
           }, py::arg("level"), "Moves to a level; returns it.")
      .def("set_faces", [](Runtime& r, std::size_t n) { r.lod->set_face_count(n); return r.lod->level(); },
           py::arg("n"), "Moves to the coarsest level with at least n faces; returns the level.")
      .def("set_vertices", [](Runtime& r, std::size_t n) { r.lod->set_vertex_count(n); return r.lod->level(); },
           py::arg("n"), "Moves to the coarsest level with at least n vertices; returns the level.")
      .def("set_error", [](Runtime& r, double e) {
             if (!(e >= 0)) pmesh::invalid_argument("error must be >= 0");
             r.lod->set_error(e);
             return r.lod->level();
           }, py::arg("error"), "Moves to the coarsest level whose recorded error is at most error.")
      .def_property_readonly("indices", [](py::object self) {
             const pm::RuntimeLod& lod = *self.cast<const Runtime&>().lod;
             return pmesh::view(lod.indices(), lod.face_count(), 3, self, false);
           }, "(face_count, 3) uint32: the active faces, as wedge indices.")
      .def_property_readonly("positions", [](py::object self) {
             const pm::RuntimeLod& lod = *self.cast<const Runtime&>().lod;
             return pmesh::view(lod.positions(), lod.wedge_count(), 3, self, false);
           }, "(wedge_count, 3) float32 per wedge.")
      .def_property_readonly("uvs", [](py::object self) -> py::object {
             const pm::RuntimeLod& lod = *self.cast<const Runtime&>().lod;
             if (!lod.uvs()) return py::none();
             return pmesh::view(lod.uvs(), lod.wedge_count(), 2, self, false);
           }, "(wedge_count, 2) float32 per wedge (NaN where none), or None.")
      .def_property_readonly("normals", [](py::object self) -> py::object {
             const pm::RuntimeLod& lod = *self.cast<const Runtime&>().lod;
             if (!lod.normals()) return py::none();
             return pmesh::view(lod.normals(), lod.wedge_count(), 3, self, false);
           }, "(wedge_count, 3) float32 per wedge (NaN where none), or None.")
      .def_property_readonly("colors", [](py::object self) -> py::object {
             const pm::RuntimeLod& lod = *self.cast<const Runtime&>().lod;
             if (!lod.colors()) return py::none();
             return pmesh::view(lod.colors(), lod.wedge_count(), lod.color_components(), self, false);
           }, "(wedge_count, 3 or 4) float32 per wedge, or None.")
      .def("to_mesh", [](const Runtime& r) { return pmesh::wrap_mesh(r.lod->to_mesh()); },
           "The active mesh as a pmesh.Mesh (one vertex per wedge in use).")
      .def("memory_bytes", [](const Runtime& r) { return r.lod->memory_bytes(); })
      .def("geomorph", [](Runtime& r, std::size_t from, std::size_t to) {
             if (from > to || to > r.lod->max_level())
               pmesh::invalid_argument("geomorph needs from <= to <= max_level");
             // With the GIL held, as every call that changes the runtime: one thread at a time.
             return Geomorph{r.lod, r.lod->geomorph(from, to), from, to};
           }, py::arg("a"), py::arg("b"),
           R"(A geomorph from level a to level b >= a (Hoppe 1996, §4.2): level b's mesh, each wedge
that level a lacks starting at its ancestor's position and attributes. Leaves the runtime at
level b. Call it with alpha in [0, 1] for the blended pmesh.Mesh.)");

  py::class_<Geomorph>(m, "Geomorph", "A geomorph between two levels (Runtime.geomorph).")
      .def("__call__", [](const Geomorph& g, double alpha) {
             pm::Mesh mesh;
             const float a = pmesh::checked_alpha(alpha);
             {
               py::gil_scoped_release release;
               mesh = g.morph.mesh(a);
             }
             return pmesh::wrap_mesh(std::move(mesh));
           }, py::arg("alpha"),
           R"(The blended mesh at alpha (0: level a's geometry, 1: level b's, both exactly), as
pmdec --morph A:B:ALPHA writes it: one vertex per vertex of level b.)")
      .def("evaluate", [](const Geomorph& g, double alpha) {
             const float a = pmesh::checked_alpha(alpha);
             const std::size_t n = g.morph.wedge_count();
             const pm::RuntimeLod& lod = *g.lod;
             py::array_t<float> positions({py::ssize_t(n), py::ssize_t(3)});
             py::object uvs = py::none(), normals = py::none(), colors = py::none();
             float *u = nullptr, *nr = nullptr, *c = nullptr;
             if (lod.uvs()) { py::array_t<float> x({py::ssize_t(n), py::ssize_t(2)}); u = x.mutable_data(); uvs = x; }
             if (lod.normals()) { py::array_t<float> x({py::ssize_t(n), py::ssize_t(3)}); nr = x.mutable_data(); normals = x; }
             if (lod.colors()) {
               py::array_t<float> x({py::ssize_t(n), py::ssize_t(lod.color_components())});
               c = x.mutable_data();
               colors = x;
             }
             float* p = positions.mutable_data();
             {
               py::gil_scoped_release release;
               g.morph.evaluate(a, p, u, nr, c);
             }
             return py::make_tuple(positions, uvs, normals, colors);
           }, py::arg("alpha"),
           "Per wedge, for a renderer: (positions, uvs, normals, colors) at alpha, None where absent.")
      .def_property_readonly("indices", [](py::object self) {
             const Geomorph& g = self.cast<const Geomorph&>();
             return pmesh::view(g.morph.indices(), g.morph.face_count(), 3, self, false);
           }, "(face_count, 3) uint32 wedge indices of level b.")
      .def_property_readonly("wedge_count", [](const Geomorph& g) { return g.morph.wedge_count(); })
      .def_property_readonly("levels", [](const Geomorph& g) { return py::make_tuple(g.from, g.to); });

  // ---- distances ----
  py::class_<Distance>(m, "SurfaceDistance", R"(Measured distance between two surfaces (Metro:
Cignoni, Rocchini and Scopigno 1998): hausdorff and rms over the samples of both directions,
forward_* from the reference's samples, backward_* from the other's, model units; diagonal
of the reference's bounding box; *_percent of it (None for a zero diagonal).)")
      .def_property_readonly("hausdorff", [](const Distance& d) { return d.d.hausdorff; })
      .def_property_readonly("rms", [](const Distance& d) { return d.d.rms; })
      .def_property_readonly("forward_max", [](const Distance& d) { return d.d.forward_max; })
      .def_property_readonly("forward_rms", [](const Distance& d) { return d.d.forward_rms; })
      .def_property_readonly("backward_max", [](const Distance& d) { return d.d.backward_max; })
      .def_property_readonly("backward_rms", [](const Distance& d) { return d.d.backward_rms; })
      .def_property_readonly("diagonal", [](const Distance& d) { return d.d.diagonal; })
      .def_property_readonly("samples", [](const Distance& d) { return d.d.samples; })
      .def_property_readonly("faces", [](const Distance& d) { return d.faces; })
      .def_property_readonly("hausdorff_percent", [](const Distance& d) { return d.percent(d.d.hausdorff); })
      .def_property_readonly("rms_percent", [](const Distance& d) { return d.percent(d.d.rms); })
      .def("__str__", &pmesh::distance_text)
      .def("__repr__", [](const Distance& d) { return "pmesh.SurfaceDistance(" + pmesh::distance_text(d) + ")"; });
  m.def("surface_distance", &pmesh::surface_distance, py::arg("reference"), py::arg("other"),
        py::kw_only(), py::arg("samples_per_face") = 10.0, py::arg("seed") = 1, py::arg("threads") = 0,
        R"(How far `other` is from `reference`, measured as pmdec --compare measures it (every
vertex and at least samples_per_face points per face of each surface, each sample's exact
distance to the other surface, both ways). Reproducible for a seed, whatever the threads.
Returns a SurfaceDistance; str() of it is pmdec --compare's line.)");
}
