#include "test_util.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <tuple>

namespace pm::test {
namespace {

namespace fs = std::filesystem;

// Union-find with path halving; enough for meshes of a few million elements.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t count) : parent_(count) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

void check_indices(const pm::Mesh& mesh) {
  const std::size_t vertex_count = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertex_count) {
      throw std::out_of_range("face " + std::to_string(i / 3) + " references vertex " +
                              std::to_string(mesh.triangles[i]) + " but the mesh has " +
                              std::to_string(vertex_count) + " vertices");
    }
  }
}

// One side of a face, a -> b with a != b, keyed by its undirected edge.
struct HalfEdge {
  uint32_t low, high;    // the undirected edge {low, high}, low < high
  bool forward;          // whether the face runs low -> high
  uint32_t from_corner;  // corner index (3 * face + k) of the side's start vertex
  uint32_t to_corner;    // corner index of its end vertex

  bool operator<(const HalfEdge& other) const {
    return std::tie(low, high, from_corner) < std::tie(other.low, other.high, other.from_corner);
  }
};

bool is_zero_area(const pm::Mesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  if (a == b || b == c || c == a) return true;
  auto corner = [&](uint32_t v, int axis) { return double{mesh.positions[3 * v + axis]}; };
  const double ux = corner(b, 0) - corner(a, 0), uy = corner(b, 1) - corner(a, 1),
               uz = corner(b, 2) - corner(a, 2);
  const double vx = corner(c, 0) - corner(a, 0), vy = corner(c, 1) - corner(a, 1),
               vz = corner(c, 2) - corner(a, 2);
  const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  return nx == 0 && ny == 0 && nz == 0;
}

}  // namespace

TopologySummary summarize_topology(const pm::Mesh& mesh) {
  check_indices(mesh);
  TopologySummary summary;
  const std::size_t vertex_count = mesh.vertex_count();
  const std::size_t face_count = mesh.face_count();
  const auto& tri = mesh.triangles;
  summary.faces = static_cast<long>(face_count);

  std::vector<char> referenced(vertex_count, 0);
  for (uint32_t v : tri) referenced[v] = 1;
  summary.vertices = std::count(referenced.begin(), referenced.end(), 1);

  for (std::size_t f = 0; f < face_count; ++f) {
    if (is_zero_area(mesh, tri[3 * f], tri[3 * f + 1], tri[3 * f + 2])) ++summary.zero_area_faces;
  }

  // Components: faces sharing a vertex are connected, so join each face's vertices.
  DisjointSets vertex_sets(vertex_count);
  for (std::size_t f = 0; f < face_count; ++f) {
    vertex_sets.unite(tri[3 * f], tri[3 * f + 1]);
    vertex_sets.unite(tri[3 * f], tri[3 * f + 2]);
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (referenced[v] && vertex_sets.find(v) == v) ++summary.components;
  }

  // All face sides, grouped by undirected edge.
  std::vector<HalfEdge> sides;
  sides.reserve(tri.size());
  for (std::size_t c = 0; c < tri.size(); ++c) {
    const std::size_t next = c - c % 3 + (c % 3 + 1) % 3;
    const uint32_t a = tri[c], b = tri[next];
    if (a == b) continue;
    sides.push_back({std::min(a, b), std::max(a, b), a < b, static_cast<uint32_t>(c),
                     static_cast<uint32_t>(next)});
  }
  std::sort(sides.begin(), sides.end());

  // Fans: corners (face, vertex) are joined when their faces share an edge at that vertex;
  // a vertex is manifold when all its corners end up in one set.
  DisjointSets corner_sets(tri.size());
  for (std::size_t f = 0; f < face_count; ++f) {
    // A face with a repeated index is one face, so its corners at that vertex are one fan.
    for (int k = 0; k < 3; ++k) {
      if (tri[3 * f + k] == tri[3 * f + (k + 1) % 3]) {
        corner_sets.unite(3 * f + k, 3 * f + (k + 1) % 3);
      }
    }
  }

  std::vector<std::pair<uint32_t, uint32_t>> boundary;  // directed boundary half-edges
  auto corner_at = [&](const HalfEdge& side, uint32_t vertex) {
    return tri[side.from_corner] == vertex ? side.from_corner : side.to_corner;
  };
  for (auto group = sides.begin(); group != sides.end();) {
    const auto group_end = std::find_if(group, sides.end(), [&](const HalfEdge& side) {
      return side.low != group->low || side.high != group->high;
    });
    const long uses = group_end - group;
    const long forward =
        std::count_if(group, group_end, [](const HalfEdge& side) { return side.forward; });
    ++summary.edges;
    if (uses > 2 || (uses == 2 && forward != 1)) ++summary.non_manifold_edges;
    if (uses == 1) boundary.emplace_back(tri[group->from_corner], tri[group->to_corner]);
    // Join the corners at each end of the edge across all faces using it.
    for (auto side = group + 1; side != group_end; ++side) {
      corner_sets.unite(corner_at(*group, group->low), corner_at(*side, side->low));
      corner_sets.unite(corner_at(*group, group->high), corner_at(*side, side->high));
    }
    group = group_end;
  }
  summary.edge_manifold = summary.non_manifold_edges == 0;

  // Count fans per vertex: the distinct corner-set roots among its corners.
  std::vector<std::vector<std::size_t>> roots_at(vertex_count);
  for (std::size_t c = 0; c < tri.size(); ++c) roots_at[tri[c]].push_back(corner_sets.find(c));
  for (auto& roots : roots_at) {
    std::sort(roots.begin(), roots.end());
    if (std::unique(roots.begin(), roots.end()) - roots.begin() > 1) {
      ++summary.non_manifold_vertices;
    }
  }
  summary.vertex_manifold = summary.non_manifold_vertices == 0;

  // Boundary loops (see the header for the rule).
  std::vector<int> out_degree(vertex_count, 0), in_degree(vertex_count, 0);
  std::vector<uint32_t> next_on_boundary(vertex_count, 0);
  for (const auto& [from, to] : boundary) {
    ++out_degree[from];
    ++in_degree[to];
    next_on_boundary[from] = to;
  }
  bool regular = true;
  for (const auto& [from, to] : boundary) {
    regular = regular && out_degree[from] == 1 && in_degree[from] == 1 && out_degree[to] == 1 &&
              in_degree[to] == 1;
  }
  if (regular) {
    std::vector<char> visited(vertex_count, 0);
    for (const auto& edge : boundary) {
      if (visited[edge.first]) continue;
      ++summary.boundary_loops;
      for (uint32_t v = edge.first; !visited[v]; v = next_on_boundary[v]) visited[v] = 1;
    }
  } else {
    DisjointSets boundary_sets(vertex_count);
    std::vector<char> on_boundary(vertex_count, 0);
    for (const auto& [from, to] : boundary) {
      boundary_sets.unite(from, to);
      on_boundary[from] = on_boundary[to] = 1;
    }
    for (std::size_t v = 0; v < vertex_count; ++v) {
      if (on_boundary[v] && boundary_sets.find(v) == v) ++summary.boundary_loops;
    }
  }

  summary.euler = summary.vertices - summary.edges + summary.faces;
  return summary;
}

std::string to_string(const TopologySummary& s) {
  std::ostringstream out;
  out << "V=" << s.vertices << " E=" << s.edges << " F=" << s.faces << " euler=" << s.euler
      << " boundary_loops=" << s.boundary_loops << " components=" << s.components
      << " edge_manifold=" << s.edge_manifold << " (" << s.non_manifold_edges << " bad)"
      << " vertex_manifold=" << s.vertex_manifold << " (" << s.non_manifold_vertices
      << " bad) zero_area_faces=" << s.zero_area_faces;
  return out.str();
}

bool operator==(const TopologySummary& a, const TopologySummary& b) {
  auto fields = [](const TopologySummary& s) {
    return std::tie(s.vertices, s.edges, s.faces, s.euler, s.boundary_loops, s.components,
                    s.edge_manifold, s.vertex_manifold, s.zero_area_faces, s.non_manifold_edges,
                    s.non_manifold_vertices);
  };
  return fields(a) == fields(b);
}

void PrintTo(const TopologySummary& summary, std::ostream* out) {
  *out << to_string(summary);
}

// ---------------------------------------------------------------------------------------

namespace {

uint32_t float_bits(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Maps float bits to an unsigned key whose order is the IEEE total order: negative values
// (sign bit set) are reversed, positive ones placed above them.
uint32_t total_order_key(float value) {
  const uint32_t bits = float_bits(value);
  return (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
}

bool face_less(const FacePositions& a, const FacePositions& b) {
  for (int i = 0; i < 9; ++i) {
    const uint32_t ka = total_order_key(a[i]), kb = total_order_key(b[i]);
    if (ka != kb) return ka < kb;
  }
  return false;
}

std::string describe_face(const FacePositions& face) {
  std::ostringstream out;
  out << std::setprecision(9);
  for (int corner = 0; corner < 3; ++corner) {
    out << (corner ? " " : "") << "(" << face[3 * corner] << ", " << face[3 * corner + 1] << ", "
        << face[3 * corner + 2] << ")";
  }
  out << " bits [" << std::hex << std::setfill('0');
  for (int i = 0; i < 9; ++i) out << (i ? " " : "") << std::setw(8) << float_bits(face[i]);
  out << "]";
  return out.str();
}

}  // namespace

std::vector<FacePositions> canonical_faces(const pm::Mesh& mesh) {
  check_indices(mesh);
  std::vector<FacePositions> faces;
  faces.reserve(mesh.face_count());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    // The smallest of the three rotations; comparing whole rotations breaks ties between
    // equal corners deterministically.
    FacePositions best{};
    for (int start = 0; start < 3; ++start) {
      FacePositions rotated;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.triangles[3 * f + (start + k) % 3];
        for (int axis = 0; axis < 3; ++axis) rotated[3 * k + axis] = mesh.positions[3 * v + axis];
      }
      if (start == 0 || face_less(rotated, best)) best = rotated;
    }
    faces.push_back(best);
  }
  std::sort(faces.begin(), faces.end(), face_less);
  return faces;
}

::testing::AssertionResult ok(const pm::Status& status) {
  if (status.is_ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << pm::error_code_name(status.code()) << ": "
                                       << status.message();
}

::testing::AssertionResult same_faces(const pm::Mesh& expected, const pm::Mesh& actual) {
  const std::vector<FacePositions> want = canonical_faces(expected);
  const std::vector<FacePositions> got = canonical_faces(actual);
  // Merge walk over the two sorted lists: equal faces pair off, the rest are differences.
  std::size_t i = 0, j = 0, only_expected = 0, only_actual = 0;
  const FacePositions* first_only_expected = nullptr;
  const FacePositions* first_only_actual = nullptr;
  while (i < want.size() || j < got.size()) {
    if (j == got.size() || (i < want.size() && face_less(want[i], got[j]))) {
      if (!first_only_expected) first_only_expected = &want[i];
      ++only_expected, ++i;
    } else if (i == want.size() || face_less(got[j], want[i])) {
      if (!first_only_actual) first_only_actual = &got[j];
      ++only_actual, ++j;
    } else {
      ++i, ++j;
    }
  }
  if (only_expected == 0 && only_actual == 0) return ::testing::AssertionSuccess();
  auto failure = ::testing::AssertionFailure();
  failure << "face multisets differ: expected has " << want.size() << " faces, actual has "
          << got.size() << "; " << only_expected << " only in expected, " << only_actual
          << " only in actual";
  if (first_only_expected)
    failure << "\n  first only in expected: " << describe_face(*first_only_expected);
  if (first_only_actual)
    failure << "\n  first only in actual:   " << describe_face(*first_only_actual);
  return failure;
}

// ---------------------------------------------------------------------------------------

std::string shared_mesh_path(const std::string& name) {
  return std::string(PM_SHARED_MESHES_DIR) + "/" + name;
}

bool shared_meshes_available() {
  std::error_code error;
  return fs::is_directory(PM_SHARED_MESHES_DIR, error);
}

void warn_no_shared_meshes() {
  static std::once_flag once;
  std::call_once(once, [] {
    std::fprintf(stderr, "\n*** WARNING: %s (looked in %s) ***\n\n", kNoSharedMeshesMessage,
                 PM_SHARED_MESHES_DIR);
  });
}

namespace {

// Sorted names of the regular files in directory whose extension is one of extensions.
std::vector<std::string> files_with_extensions(const std::string& directory,
                                               const std::vector<std::string>& extensions) {
  std::vector<std::string> names;
  std::error_code error;
  if (!fs::is_directory(directory, error)) return names;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    if (!entry.is_regular_file(error)) continue;
    const std::string extension = entry.path().extension().string();
    if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

std::vector<std::string> shared_mesh_names() {
  return files_with_extensions(PM_SHARED_MESHES_DIR, {".obj", ".off", ".ply"});
}

std::vector<std::string> sample_mesh_paths() {
  std::vector<std::string> paths;
  for (const auto& name : files_with_extensions(PM_SAMPLES_DIR, {".obj"})) {
    paths.push_back(sample_mesh_path(name));
  }
  return paths;
}

std::string sample_mesh_path(const std::string& name) {
  return std::string(PM_SAMPLES_DIR) + "/" + name;
}

pm::Mesh load_simple_obj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  pm::Mesh mesh;
  std::string line;
  std::vector<uint32_t> polygon;
  for (long line_number = 1; std::getline(in, line); ++line_number) {
    auto fail = [&](const std::string& reason) {
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " + reason);
    };
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      for (int axis = 0; axis < 3; ++axis) {
        std::string word;
        words >> word;
        float value = 0;
        const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
        if (word.empty() || error != std::errc() || end != word.data() + word.size()) {
          fail("bad vertex coordinate '" + word + "'");
        }
        mesh.positions.push_back(value);
      }
    } else if (keyword == "f") {
      polygon.clear();
      const long vertex_count = static_cast<long>(mesh.vertex_count());
      for (std::string corner; words >> corner;) {
        const std::string index_text = corner.substr(0, corner.find('/'));
        long index = 0;
        const char* first = index_text.data();
        const char* last = first + index_text.size();
        const auto [end, error] = std::from_chars(first, last, index);
        if (index_text.empty() || error != std::errc() || end != last) {
          fail("bad face corner '" + corner + "'");
        }
        // 1-based, or negative: relative to the vertices read so far (-1 = the last one).
        const long zero_based = index < 0 ? vertex_count + index : index - 1;
        if (index == 0 || zero_based < 0 || zero_based >= vertex_count) {
          fail("face index " + std::to_string(index) + " out of range (" +
               std::to_string(vertex_count) + " vertices so far)");
        }
        polygon.push_back(static_cast<uint32_t>(zero_based));
      }
      if (polygon.size() < 3) fail("face with fewer than 3 corners");
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        mesh.triangles.insert(mesh.triangles.end(), {polygon[0], polygon[k], polygon[k + 1]});
      }
    }
  }
  if (in.bad()) throw std::runtime_error(path + ": read error");
  return mesh;
}

// ---------------------------------------------------------------------------------------

namespace {

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

// Makes fd the child's standard descriptor `target`, keeping it open across exec.
void install_as(int fd, int target) {
  if (fd == target) {
    ::fcntl(fd, F_SETFD, 0);  // pipe2's O_CLOEXEC would otherwise close it at exec
  } else {
    ::dup2(fd, target);
  }
}

}  // namespace

CommandResult run_command(const std::vector<std::string>& argv, const std::string& stdin_data) {
  if (argv.empty()) throw std::invalid_argument("run_command: empty argv");
  // Built before fork: the child of a possibly multi-threaded process may not allocate.
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);

  // [0] read end, [1] write end; all close-on-exec so concurrent children don't inherit
  // them. exec_status reports a failed exec: the child writes errno there; a successful
  // exec closes it, so the parent reads end-of-file.
  int in[2], out[2], err[2], exec_status[2];
  if (::pipe2(in, O_CLOEXEC) != 0) throw_errno("pipe2");
  if (::pipe2(out, O_CLOEXEC) != 0) throw_errno("pipe2");
  if (::pipe2(err, O_CLOEXEC) != 0) throw_errno("pipe2");
  if (::pipe2(exec_status, O_CLOEXEC) != 0) throw_errno("pipe2");

  const pid_t pid = ::fork();
  if (pid < 0) throw_errno("fork");
  if (pid == 0) {
    install_as(in[0], 0);
    install_as(out[1], 1);
    install_as(err[1], 2);
    // The test process may ignore or block SIGPIPE; the program should get the defaults.
    ::signal(SIGPIPE, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::execvp(args[0], args.data());
    const int exec_errno = errno;
    [[maybe_unused]] ssize_t ignored = ::write(exec_status[1], &exec_errno, sizeof exec_errno);
    ::_exit(127);
  }

  close_fd(in[0]);
  close_fd(out[1]);
  close_fd(err[1]);
  close_fd(exec_status[1]);

  CommandResult result;
  int exec_errno = 0;
  ssize_t got;
  do {
    got = ::read(exec_status[0], &exec_errno, sizeof exec_errno);
  } while (got < 0 && errno == EINTR);
  close_fd(exec_status[0]);
  const bool exec_failed = got == static_cast<ssize_t>(sizeof exec_errno);

  // Writing to a program that exits without reading its stdin raises SIGPIPE, which would
  // kill the test process: block it in this thread while we write, and discard it after.
  sigset_t pipe_signal, old_mask;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  ::pthread_sigmask(SIG_BLOCK, &pipe_signal, &old_mask);

  int stdin_fd = in[1];
  std::size_t written = 0;
  if (stdin_data.empty() || exec_failed) {
    close_fd(stdin_fd);
  } else {
    ::fcntl(stdin_fd, F_SETFL, ::fcntl(stdin_fd, F_GETFL) | O_NONBLOCK);
  }
  int stdout_fd = out[0], stderr_fd = err[0];
  char buffer[65536];
  while (stdout_fd >= 0 || stderr_fd >= 0 || stdin_fd >= 0) {
    pollfd fds[3];
    int count = 0;
    if (stdin_fd >= 0) fds[count++] = {stdin_fd, POLLOUT, 0};
    if (stdout_fd >= 0) fds[count++] = {stdout_fd, POLLIN, 0};
    if (stderr_fd >= 0) fds[count++] = {stderr_fd, POLLIN, 0};
    if (::poll(fds, count, -1) < 0) {
      if (errno == EINTR) continue;
      throw_errno("poll");
    }
    for (int i = 0; i < count; ++i) {
      if (fds[i].revents == 0) continue;
      if (fds[i].fd == stdin_fd) {
        const ssize_t n =
            ::write(stdin_fd, stdin_data.data() + written, stdin_data.size() - written);
        if (n > 0) written += static_cast<std::size_t>(n);
        // EPIPE: the program closed its stdin; the rest of the data is not wanted.
        if (written == stdin_data.size() || (n < 0 && errno != EAGAIN && errno != EINTR)) {
          close_fd(stdin_fd);
        }
      } else {
        int& fd = fds[i].fd == stdout_fd ? stdout_fd : stderr_fd;
        std::string& sink = fds[i].fd == stdout_fd ? result.out : result.err;
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n > 0) {
          sink.append(buffer, static_cast<std::size_t>(n));
        } else if (n == 0 || errno != EINTR) {
          close_fd(fd);
        }
      }
    }
  }

  // Consume a SIGPIPE raised by our writes before restoring the mask.
  sigset_t pending;
  sigpending(&pending);
  if (sigismember(&pending, SIGPIPE)) {
    const timespec no_wait{0, 0};
    ::sigtimedwait(&pipe_signal, nullptr, &no_wait);
  }
  ::pthread_sigmask(SIG_SETMASK, &old_mask, nullptr);

  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw_errno("waitpid");
  }
  if (WIFEXITED(status)) {
    result.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.exit_code = 128 + WTERMSIG(status);
  }
  if (exec_failed) {
    result.exit_code = 127;
    result.err = "cannot execute " + argv[0] + ": " + std::strerror(exec_errno);
  }
  return result;
}

TempDir::TempDir() {
  // TMPDIR as a user or a CI runner sets it, perhaps relative or with a trailing slash
  // ("/tmp/"): made absolute and lexically normal, so that paths built on path() read as the
  // tools print them ("/tmp//pm_test_x/a.pm" would not).
  const char* base = std::getenv("TMPDIR");
  std::string directory =
      fs::absolute(fs::path(base && *base ? base : "/tmp")).lexically_normal().string();
  while (directory.size() > 1 && directory.back() == '/') directory.pop_back();
  std::string pattern = directory + "/pm_test_XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) throw_errno("mkdtemp " + pattern);
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;  // a destructor must not throw; a leftover temp dir is harmless
  fs::remove_all(path_, ignored);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path + " for reading");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw std::runtime_error("error reading " + path);
  return bytes.str();
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open " + path + " for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("error writing " + path);
}

bool file_exists(const std::string& path) {
  std::error_code error;
  return fs::exists(path, error);
}

// ---------------------------------------------------------------------------------------
// Attributed faces
// ---------------------------------------------------------------------------------------

namespace {

std::vector<uint32_t> attributed_corner(const pm::Mesh& m, std::size_t face, int k) {
  const uint32_t v = m.triangles[3 * face + k];
  std::vector<uint32_t> c;
  for (int i = 0; i < 3; ++i) c.push_back(float_bits(m.positions[3 * std::size_t{v} + i]));
  for (uint32_t i = 0; i < m.color_components; ++i)
    c.push_back(float_bits(m.colors[std::size_t{m.color_components} * v + i]));
  if (m.has_uvs()) {
    const uint32_t t = m.uv_indices[3 * face + k];
    for (int i = 0; i < 2; ++i)
      c.push_back(t == pm::kNoAttribute ? 0xFFFFFFFFu : float_bits(m.uvs[2 * std::size_t{t} + i]));
  }
  if (m.has_normals()) {
    const uint32_t n = m.normal_indices[3 * face + k];
    for (int i = 0; i < 3; ++i)
      c.push_back(n == pm::kNoAttribute ? 0xFFFFFFFFu
                                        : float_bits(m.normals[3 * std::size_t{n} + i]));
  }
  return c;
}

std::string describe(const AttributedFace& face) {
  std::ostringstream out;
  for (const auto& corner : face.corners) {
    out << "[";
    for (std::size_t i = 0; i < corner.size(); ++i)
      out << (i ? " " : "") << std::hex << std::setw(8) << std::setfill('0') << corner[i];
    out << "]";
  }
  if (!face.material.empty()) out << " material " << face.material;
  return out.str();
}

}  // namespace

bool AttributedFace::operator<(const AttributedFace& o) const {
  return std::tie(corners, material) < std::tie(o.corners, o.material);
}
bool AttributedFace::operator==(const AttributedFace& o) const {
  return corners == o.corners && material == o.material;
}

std::vector<AttributedFace> attributed_faces(const pm::Mesh& m) {
  std::vector<AttributedFace> faces;
  faces.reserve(m.face_count());
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    AttributedFace face;
    std::array<std::vector<uint32_t>, 3> corners;
    for (int k = 0; k < 3; ++k) corners[k] = attributed_corner(m, f, k);
    // The smallest of the three rotations as a whole: with two equal corners, the smallest
    // corner alone would not pick one rotation.
    for (int start = 0; start < 3; ++start) {
      const std::array<std::vector<uint32_t>, 3> rotated = {
          corners[start], corners[(start + 1) % 3], corners[(start + 2) % 3]};
      if (start == 0 || rotated < face.corners) face.corners = rotated;
    }
    if (m.has_materials() && m.face_materials[f] != pm::kNoAttribute)
      face.material = m.material_names[m.face_materials[f]];
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

::testing::AssertionResult same_attributed_faces(const pm::Mesh& expected, const pm::Mesh& actual) {
  const auto a = attributed_faces(expected), b = attributed_faces(actual);
  if (a == b) return ::testing::AssertionSuccess();
  std::size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  auto failure = ::testing::AssertionFailure();
  failure << "attributed faces differ: expected " << a.size() << " faces, actual " << b.size()
          << "; first difference at sorted face " << i;
  if (i < a.size()) failure << "\n  expected " << describe(a[i]);
  if (i < b.size()) failure << "\n  actual   " << describe(b[i]);
  return failure;
}

// A bumpy n x n grid over [0, 1]^2 (n even) with three kinds of discontinuity crossing it:
// a UV seam along x = 0.5 (two charts), a normal crease along y = 0.5, a material border
// along the diagonal x = y (which the triangles' diagonals follow); and a colour per vertex.
pm::Mesh seamed_grid(int n) {
  pm::Mesh m;
  auto id = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / n, y = float(j) / n;
      m.positions.insert(m.positions.end(),
                         {x, y, 0.05f * std::sin(7.0f * x) * std::cos(5.0f * y)});
      m.colors.insert(m.colors.end(), {x, y, 0.5f});
    }
  m.color_components = 3;
  // UV charts: left keeps (x, y); right is shifted, so x = 0.5 has two UVs per vertex.
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.uvs.insert(m.uvs.end(), {float(i) / n, float(j) / n});
  const uint32_t right_chart = static_cast<uint32_t>(m.uvs.size() / 2);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.uvs.insert(m.uvs.end(), {float(i) / n + 0.25f, float(j) / n});
  m.normals = {0, 0, 1, 0, 0.6f, 0.8f};
  m.material_names = {"red", "blue"};
  m.material_libraries = {"grid.mtl"};
  auto add = [&](int ai, int aj, int bi, int bj, int ci, int cj) {
    const int cx2 = ai + bi + ci, cy2 = aj + bj + cj;  // 3 x centroid, in grid steps
    const bool right = 2 * cx2 > 3 * n, top = 2 * cy2 > 3 * n;
    m.triangles.insert(m.triangles.end(), {id(ai, aj), id(bi, bj), id(ci, cj)});
    for (auto [i, j] : {std::pair{ai, aj}, {bi, bj}, {ci, cj}}) {
      m.uv_indices.push_back((right ? right_chart : 0) + id(i, j));
      m.normal_indices.push_back(top ? 1 : 0);
    }
    m.face_materials.push_back(cy2 > cx2 ? 1 : 0);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      add(i, j, i + 1, j, i + 1, j + 1);
      add(i, j, i + 1, j + 1, i, j + 1);
    }
  return m;
}

::testing::AssertionResult keeps_topology(const TopologySummary& in, const TopologySummary& out) {
  const bool same = out.euler == in.euler && out.boundary_loops == in.boundary_loops &&
                    out.components == in.components && out.edge_manifold == in.edge_manifold &&
                    out.vertex_manifold == in.vertex_manifold &&
                    out.non_manifold_edges == in.non_manifold_edges &&
                    out.non_manifold_vertices == in.non_manifold_vertices &&
                    out.zero_area_faces <= in.zero_area_faces;
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "level " << to_string(out) << " vs input " << to_string(in);
}

pm::Mesh without_flat_faces(const pm::Mesh& mesh) {
  pm::Mesh out = mesh;
  out.triangles.clear();
  out.uv_indices.clear();
  out.normal_indices.clear();
  out.face_materials.clear();
  auto same = [&](uint32_t a, uint32_t b) {
    return std::equal(&mesh.positions[3 * std::size_t{a}], &mesh.positions[3 * std::size_t{a}] + 3,
                      &mesh.positions[3 * std::size_t{b}]);
  };
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* t = &mesh.triangles[3 * f];
    if (same(t[0], t[1]) || same(t[1], t[2]) || same(t[0], t[2])) continue;
    out.triangles.insert(out.triangles.end(), t, t + 3);
    if (mesh.has_uvs())
      out.uv_indices.insert(out.uv_indices.end(), &mesh.uv_indices[3 * f], &mesh.uv_indices[3 * f] + 3);
    if (mesh.has_normals())
      out.normal_indices.insert(out.normal_indices.end(), &mesh.normal_indices[3 * f],
                                &mesh.normal_indices[3 * f] + 3);
    if (mesh.has_materials()) out.face_materials.push_back(mesh.face_materials[f]);
  }
  return out;
}

}  // namespace pm::test
