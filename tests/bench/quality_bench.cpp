// The quality benchmark (issue 3): how close to the input each simplifier's LOD stays, at
// the same face count, measured by one piece of code for every method.
//
// For each mesh and each target fraction of its faces, each method produces a mesh of about
// that many faces:
//   pmenc schroeder, pmenc quadric  pm::encode once per metric (the one collapse loop, since
//                                   issue 25), geometry only like the peers (drop_attributes);
//                                   the LOD is the finest level with at most the target's
//                                   faces (pm::extract_level)
//   pmenc REFERENCE (3cb92db)       the pmenc of an older commit (--reference-pmenc), run as
//                                   a process with the same options; its .pm is read back
//                                   with today's decoder and its levels taken the same way
//   meshopt_simplify                meshoptimizer 0.18, no options, no error limit
//   OpenMesh Decimater              DecimaterT with ModQuadricT alone, not binary; and a
//                                   variant with ModNormalFlippingT, pmenc's 90-degree rule
//   vtkDecimatePro                  through vtk_decimate.py, PreserveTopologyOn
// and each LOD is compared with the input by pm::measure_surface_distance (Metro-style,
// Cignoni, Rocchini and Scopigno 1998): Hausdorff and RMS distance, both ways, in percent of
// the input's bounding-box diagonal. The output is a markdown report; see README.md.
#include <meshoptimizer.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bench_report.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/surface_distance.h"

namespace {

namespace fs = std::filesystem;
using pm::bench::command_output;
using pm::bench::distinguishable_pair;
using pm::bench::shell_quoted;
using pm::bench::significant;
using pm::bench::with_thousands;
using Clock = std::chrono::steady_clock;

// A method that ends more than this fraction above its face target has stalled: it cannot
// simplify further under its own rules (topology, borders, legality).
constexpr double kStallTolerance = 0.02;

// The rows of each target, in this order.
enum class Method {
  kPmencSchroeder,
  kPmencSchroederReference,  // the reference commit's pmenc (--reference-pmenc)
  kPmencQuadric,
  kPmencQuadricReference,
  kMeshopt,
  kOpenMesh,
  kOpenMeshNormalFlipping,  // a variant: with pmenc's own 90-degree normal-flip rule
  kVtk,
};
constexpr std::array<Method, 8> kMethods = {
    Method::kPmencSchroeder, Method::kPmencSchroederReference, Method::kPmencQuadric,
    Method::kPmencQuadricReference, Method::kMeshopt, Method::kOpenMesh,
    Method::kOpenMeshNormalFlipping, Method::kVtk};
constexpr std::size_t index_of(Method method) {
  return static_cast<std::size_t>(method);
}

bool is_pmenc(Method method) {
  return index_of(method) <= index_of(Method::kPmencQuadricReference);
}

// The reference commit's rows are named after it: "pmenc 3cb92db quadric".
std::string method_name(Method method, const std::string& reference_label) {
  switch (method) {
    case Method::kPmencSchroeder:
      return "pmenc schroeder";
    case Method::kPmencSchroederReference:
      return "pmenc " + reference_label + " schroeder";
    case Method::kPmencQuadric:
      return "pmenc quadric";
    case Method::kPmencQuadricReference:
      return "pmenc " + reference_label + " quadric";
    case Method::kMeshopt:
      return "meshopt_simplify";
    case Method::kOpenMesh:
      return "OpenMesh ModQuadric";
    case Method::kOpenMeshNormalFlipping:
      return "OpenMesh ModQuadric+NormalFlipping";
    case Method::kVtk:
      return "vtkDecimatePro";
  }
  return "?";
}

struct Settings {
  std::vector<std::string> inputs;  // files or directories
  std::vector<double> targets = {0.5, 0.1, 0.02};
  std::string out_path;        // empty: standard output only
  std::string dump_directory;  // --dump: every LOD is written there as OBJ, to be looked at
  bool use_vtk = true;
  std::string vtk_script = PM_BENCH_VTK_SCRIPT;
  std::string python = "/usr/bin/python3";
  // --reference-pmenc: the pmenc built from an older commit (run_quality.sh builds 3cb92db's:
  // the former default loop, which issue 25's one loop must stay within 5% of); empty: its
  // rows are n/a.
  std::string reference_pmenc;
  std::string reference_label = "reference";  // --reference-label, the rows' name
};

// One method's LOD at one target, measured.
struct Outcome {
  bool available = false;  // false: the method could not run (n/a), see note
  std::size_t faces = 0;
  double hausdorff_percent = 0;
  double rms_percent = 0;
  double milliseconds = 0;
  bool stalled = false;
  std::string note;
};

// One mesh and one target: the outcome of every method, in kMethods order.
struct TargetRow {
  double fraction = 0;
  std::size_t target_faces = 0;
  std::array<Outcome, kMethods.size()> outcomes;
  // pmenc schroeder measured at vtkDecimatePro's face count where vtk stalled, so the two
  // are still compared at the same face count.
  std::optional<Outcome> schroeder_at_vtk_faces;
};

struct MeshReport {
  std::string name;
  std::size_t faces = 0, vertices = 0;
  double diagonal = 0;
  // Indexed by Method; only pmenc's entries are used: one encode gives all its LODs.
  std::array<double, kMethods.size()> encode_ms{};
  std::size_t openmesh_refused_faces = 0;
  std::string repairs;  // what pm::encode repaired, when anything
  std::vector<TargetRow> rows;
};

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What a method hands over: its LOD and the time it took, or why there is none.
struct Simplified {
  bool ok = false;
  pm::Mesh lod;
  double milliseconds = 0;
  std::string note;
};

// --- Measuring: the one piece of code every method's LOD goes through. ---

Outcome measure(const pm::Mesh& original, const Simplified& simplified, std::size_t target_faces) {
  Outcome outcome;
  outcome.milliseconds = simplified.milliseconds;
  outcome.note = simplified.note;
  if (!simplified.ok) return outcome;
  outcome.faces = simplified.lod.face_count();
  outcome.stalled = static_cast<double>(outcome.faces) >
                    static_cast<double>(target_faces) * (1 + kStallTolerance);
  if (outcome.faces == 0) {
    outcome.note = "no faces left";
    return outcome;
  }
  pm::SurfaceDistance distance;
  if (pm::Status s =
          pm::measure_surface_distance(original, simplified.lod, pm::DistanceOptions{}, distance);
      !s) {
    outcome.note = "measure failed: " + s.message();
    return outcome;
  }
  outcome.hausdorff_percent = 100.0 * distance.hausdorff / distance.diagonal;
  outcome.rms_percent = 100.0 * distance.rms / distance.diagonal;
  outcome.available = true;
  return outcome;
}

// --- pmenc: one encode per metric yields every LOD. ---

// The finest level with at most n faces. level_for_faces gives the coarsest with at least
// n; a split adds one or two faces, so that level may be one face over, and the level
// before it is then under.
std::size_t level_at_most_faces(const pm::ProgressiveMesh& progressive, std::size_t n) {
  std::size_t level = pm::level_for_faces(progressive, n);
  if (level > 0 && pm::faces_at_level(progressive, level) > n) --level;
  return level;
}

Simplified pmenc_level(const pm::ProgressiveMesh& progressive, std::size_t target_faces,
                       double encode_ms) {
  Simplified result;
  result.lod = pm::extract_level(progressive, level_at_most_faces(progressive, target_faces));
  result.milliseconds = encode_ms;
  result.ok = true;
  return result;
}

// --- meshoptimizer ---

Simplified meshopt_simplified(const pm::Mesh& original, std::size_t target_faces) {
  Simplified result;
  std::vector<unsigned int> indices(original.triangles.size());
  // target_error is relative to the mesh's extent; FLT_MAX lifts the limit, so only the
  // face target (and meshopt's topology rules) stops it, as for the other methods.
  const auto start = Clock::now();
  const std::size_t index_count =
      meshopt_simplify(indices.data(), original.triangles.data(), original.triangles.size(),
                       original.positions.data(), original.vertex_count(), 3 * sizeof(float),
                       3 * target_faces, FLT_MAX, /*options=*/0, /*result_error=*/nullptr);
  result.milliseconds = milliseconds_since(start);
  // The indices refer to the original vertex buffer; unreferenced vertices are not part
  // of the surface that is measured.
  result.lod.positions = original.positions;
  result.lod.triangles.assign(indices.begin(), indices.begin() + index_count);
  result.ok = true;
  return result;
}

// --- OpenMesh ---

using OpenMeshTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Faces OpenMesh's half-edge structure refuses (a complex edge or vertex) get their own
// copies of their vertices, as OpenMesh's own file readers do, so no surface is lost.
OpenMeshTriMesh to_openmesh(const pm::Mesh& mesh, std::size_t& refused_faces) {
  OpenMeshTriMesh result;
  std::vector<OpenMeshTriMesh::VertexHandle> handles(mesh.vertex_count());
  auto point = [&](uint32_t v) {
    return OpenMeshTriMesh::Point(mesh.positions[3 * v], mesh.positions[3 * v + 1],
                                  mesh.positions[3 * v + 2]);
  };
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) handles[v] = result.add_vertex(point(v));
  refused_faces = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* corners = &mesh.triangles[3 * f];
    if (result.add_face(handles[corners[0]], handles[corners[1]], handles[corners[2]]).is_valid())
      continue;
    ++refused_faces;
    result.add_face(result.add_vertex(point(corners[0])), result.add_vertex(point(corners[1])),
                    result.add_vertex(point(corners[2])));
  }
  return result;
}

pm::Mesh from_openmesh(const OpenMeshTriMesh& mesh) {
  pm::Mesh result;
  result.positions.reserve(3 * mesh.n_vertices());
  for (const auto vertex : mesh.vertices()) {
    const auto& p = mesh.point(vertex);
    result.positions.insert(result.positions.end(), {p[0], p[1], p[2]});
  }
  result.triangles.reserve(3 * mesh.n_faces());
  for (const auto face : mesh.faces())
    for (const auto vertex : face.vertices())
      result.triangles.push_back(static_cast<uint32_t>(vertex.idx()));
  return result;
}

// With guard_normals, ModNormalFlippingT at its default 90 degrees joins ModQuadricT: no
// collapse may turn a face normal by more than that, which is pmenc's own rule
// (EncodeOptions::max_normal_flip_deg); ModQuadricT alone accepts fold-overs.
Simplified openmesh_simplified(const pm::Mesh& original, std::size_t target_faces,
                               bool guard_normals, std::size_t& refused_faces) {
  Simplified result;
  OpenMeshTriMesh mesh = to_openmesh(original, refused_faces);
  if (guard_normals) {
    // ModNormalFlippingT wants face normals; computed here, untimed, as it would compute them.
    mesh.request_face_normals();
    mesh.update_face_normals();
  }
  {
    // Timed: the decimater's setup (status bits, quadrics) and the decimation itself; not
    // building the mesh above nor the garbage collection after it.
    const auto start = Clock::now();
    OpenMesh::Decimater::DecimaterT<OpenMeshTriMesh> decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<OpenMeshTriMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();  // priority only, no error limit
    OpenMesh::Decimater::ModNormalFlippingT<OpenMeshTriMesh>::Handle normal_flipping;
    if (guard_normals) {
      decimater.add(normal_flipping);
      decimater.module(normal_flipping).set_max_normal_deviation(90.0);
    }
    decimater.initialize();
    decimater.decimate_to_faces(0, target_faces);
    result.milliseconds = milliseconds_since(start);
    // Before the decimater goes: it releases the status bits that garbage_collection needs
    // to see which elements the collapses deleted.
    mesh.garbage_collection();
  }
  result.lod = from_openmesh(mesh);
  if (refused_faces > 0)
    result.note = std::to_string(refused_faces) + " input faces refused as complex";
  result.ok = true;
  return result;
}

// --- VTK, through vtk_decimate.py ---

// Exit status 3 of the script: VTK's Python modules are missing.
constexpr int kVtkMissingStatus = 3;

Simplified vtk_simplified(const Settings& settings, const fs::path& input_obj,
                          const fs::path& output_obj, std::size_t target_faces, bool& vtk_missing) {
  Simplified result;
  const std::string command =
      shell_quoted(settings.python) + " " + shell_quoted(settings.vtk_script) + " " +
      shell_quoted(input_obj.string()) + " " + std::to_string(target_faces) + " " +
      shell_quoted(output_obj.string());
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    result.note = "cannot run " + settings.python;
    return result;
  }
  std::string printed;
  std::array<char, 256> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) printed += buffer.data();
  const int status = pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    vtk_missing = WIFEXITED(status) && WEXITSTATUS(status) == kVtkMissingStatus;
    result.note = vtk_missing ? "VTK not installed" : "vtk_decimate.py failed";
    return result;
  }
  result.milliseconds = 1000.0 * std::strtod(printed.c_str(), nullptr);
  if (pm::Status s = pm::read_mesh(output_obj.string(), result.lod); !s) {
    result.note = "cannot read VTK's output: " + s.message();
    return result;
  }
  result.ok = true;
  return result;
}

// --- One mesh ---

// --dump: "cow.obj-580-pmenc_quadric.obj", for looking at what a number means.
void dump_lod(const std::string& directory, const std::string& mesh_name, std::size_t target_faces,
              std::string method_slug, const pm::Mesh& lod) {
  std::replace(method_slug.begin(), method_slug.end(), ' ', '_');
  const fs::path path = fs::path(directory) / (mesh_name + "-" + std::to_string(target_faces) +
                                               "-" + method_slug + ".obj");
  std::string bytes;
  if (pm::Status s = pm::write_mesh_to_memory(lod, pm::MeshFormat::kObj, bytes); !s) return;
  std::ofstream(path, std::ios::binary) << bytes;
}

// "duplicated vertices 1, complex edges 2": the repairs pm::encode made, zero counts left out.
std::string repair_summary(const pm::RepairReport& repair) {
  const std::pair<const char*, std::size_t> counts[] = {
      {"duplicated vertices", repair.vertices_duplicated},
      {"complex edges", repair.complex_edges},
      {"carried faces", repair.carried_faces},
      {"loose vertices", repair.loose_vertices}};
  std::string text;
  for (const auto& [what, count] : counts) {
    if (count == 0) continue;
    if (!text.empty()) text += ", ";
    text += std::string(what) + " " + std::to_string(count);
  }
  return text;
}

bool encode_timed(const pm::Mesh& mesh, pm::Metric metric, pm::ProgressiveMesh& progressive,
                  double& milliseconds, pm::EncodeStats& stats) {
  pm::EncodeOptions options;
  options.metric = metric;
  // Geometry only, like the peers, which are given positions and triangles alone: kept
  // attributes would hold UV seams and add texture error to the cost (issue 4), a handicap
  // the peers do not carry here. uv.md (pm_bench_uv) compares with attributes on both sides.
  options.drop_attributes = true;
  const auto start = Clock::now();
  const pm::Status s = pm::encode(mesh, options, progressive, &stats);
  milliseconds = milliseconds_since(start);
  if (!s) std::cerr << "  encode failed: " << s.message() << "\n";
  return s.is_ok();
}

// The reference commit's pmenc on the mesh file, as a process: geometry only like
// encode_timed's (--drop-attributes), the metric given, its default loop (--fast-from 0:
// 3cb92db took its fast loop from 1,000,000 faces on), the rest at that commit's defaults,
// which EncodeOptions{} had then too. Its .pm is read with today's decoder (the format has
// not changed: tests/data/golden still decodes). The time is the whole process: reading the
// mesh, encoding and writing the .pm. False, with the reason in `note`, when it fails.
bool reference_encode(const Settings& settings, const fs::path& input, pm::Metric metric,
                      const fs::path& scratch, pm::ProgressiveMesh& progressive,
                      double& milliseconds, std::string& note) {
  const fs::path output = scratch / "reference.pm";
  const std::string command =
      shell_quoted(settings.reference_pmenc) + " --drop-attributes --fast-from 0 --metric " +
      (metric == pm::Metric::kSchroeder ? "schroeder" : "quadric") + " -q " +
      shell_quoted(input.string()) + " -o " + shell_quoted(output.string());
  const auto start = Clock::now();
  const int status = std::system(command.c_str());
  milliseconds = milliseconds_since(start);
  if (status != 0) {
    note = settings.reference_pmenc + " failed";
    std::cerr << "quality_bench: " << command << ": failed (exit status " << status << ")\n";
    return false;
  }
  std::ifstream file(output, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (pm::Status s = pm::read_pm(bytes, progressive); !s) {
    note = "cannot read its .pm: " + s.message();
    std::cerr << "quality_bench: " << output.string() << ": " << note << "\n";
    return false;
  }
  return true;
}

std::optional<MeshReport> run_mesh(const fs::path& path, const Settings& settings,
                                   const fs::path& scratch, bool& vtk_available) {
  MeshReport report;
  report.name = path.filename().string();
  pm::Mesh original;
  if (pm::Status s = pm::read_mesh(path.string(), original); !s) {
    std::cerr << "quality_bench: " << path.string() << ": " << s.message() << " (skipped)\n";
    return std::nullopt;
  }
  report.faces = original.face_count();
  report.vertices = original.vertex_count();
  report.diagonal = pm::bounding_box_diagonal(original.positions);
  std::cerr << "[bench] " << report.name << ": " << report.faces << " faces\n";

  // Each pmenc method's sequence, indexed by Method; the reference's stays empty when it
  // cannot run (its rows are then n/a, with the reason).
  std::array<std::optional<pm::ProgressiveMesh>, kMethods.size()> encoded;
  std::string reference_note = "no --reference-pmenc";
  for (const Method method : kMethods) {
    if (!is_pmenc(method)) continue;
    const pm::Metric metric =
        index_of(method) < index_of(Method::kPmencQuadric) ? pm::Metric::kSchroeder
                                                             : pm::Metric::kQuadric;
    pm::ProgressiveMesh progressive;
    double& milliseconds = report.encode_ms[index_of(method)];
    if (method == Method::kPmencSchroederReference || method == Method::kPmencQuadricReference) {
      if (settings.reference_pmenc.empty()) continue;
      if (!reference_encode(settings, path, metric, scratch, progressive, milliseconds,
                            reference_note))
        continue;
    } else {
      pm::EncodeStats stats;
      if (!encode_timed(original, metric, progressive, milliseconds, stats))
        return std::nullopt;
      if (method == Method::kPmencQuadric) report.repairs = repair_summary(stats.repair);
    }
    std::cerr << "[bench]   " << method_name(method, settings.reference_label) << " encode: "
              << milliseconds << " ms\n";
    encoded[index_of(method)] = std::move(progressive);
  }

  // VTK reads the input as written by pm's own OBJ writer: positions and faces only. The
  // attributes are left out: vtkOBJReader splits a vertex per texture coordinate, so a UV
  // seam would reach vtkDecimatePro as a boundary, free to move (BoundaryVertexDeletionOn).
  const fs::path input_obj = scratch / "input.obj";
  const fs::path output_obj = scratch / "vtk_output.obj";
  if (vtk_available) {
    pm::Mesh geometry;
    geometry.positions = original.positions;
    geometry.triangles = original.triangles;
    std::string bytes;
    if (pm::Status s = pm::write_mesh_to_memory(geometry, pm::MeshFormat::kObj, bytes); !s) {
      std::cerr << "quality_bench: cannot serialize " << report.name << ": " << s.message() << "\n";
      return std::nullopt;
    }
    std::ofstream(input_obj, std::ios::binary) << bytes;
  }

  for (double fraction : settings.targets) {
    TargetRow row;
    row.fraction = fraction;
    row.target_faces = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(fraction * static_cast<double>(report.faces))));
    std::array<Simplified, kMethods.size()> lods;
    for (const Method method : kMethods) {
      if (!is_pmenc(method)) continue;
      const std::size_t m = index_of(method);
      if (encoded[m])
        lods[m] = pmenc_level(*encoded[m], row.target_faces, report.encode_ms[m]);
      else
        lods[m].note = reference_note;
    }
    lods[index_of(Method::kMeshopt)] = meshopt_simplified(original, row.target_faces);
    lods[index_of(Method::kOpenMesh)] = openmesh_simplified(
        original, row.target_faces, /*guard_normals=*/false, report.openmesh_refused_faces);
    lods[index_of(Method::kOpenMeshNormalFlipping)] = openmesh_simplified(
        original, row.target_faces, /*guard_normals=*/true, report.openmesh_refused_faces);
    Simplified& vtk_lod = lods[index_of(Method::kVtk)];
    if (vtk_available) {
      bool vtk_missing = false;
      vtk_lod = vtk_simplified(settings, input_obj, output_obj, row.target_faces, vtk_missing);
      if (vtk_missing) {
        vtk_available = false;
        std::cerr << "\n*** NOTE: VTK's Python modules are missing (apt-get install python3-vtk9)."
                     "\n*** The vtkDecimatePro column is n/a.\n\n";
      }
    } else {
      vtk_lod.note = settings.use_vtk ? "VTK not installed" : "--no-vtk";
    }

    auto& outcomes = row.outcomes;
    for (std::size_t m = 0; m < kMethods.size(); ++m) {
      outcomes[m] = measure(original, lods[m], row.target_faces);
      if (!settings.dump_directory.empty() && lods[m].ok)
        dump_lod(settings.dump_directory, report.name, row.target_faces,
                 method_name(kMethods[m], settings.reference_label), lods[m].lod);
    }
    // Where vtk stalls, pmenc schroeder is also measured at vtk's face count.
    const Outcome& vtk = outcomes[index_of(Method::kVtk)];
    if (vtk.available && vtk.stalled) {
      row.schroeder_at_vtk_faces = measure(
          original,
          pmenc_level(*encoded[index_of(Method::kPmencSchroeder)], vtk.faces,
                      report.encode_ms[index_of(Method::kPmencSchroeder)]),
          vtk.faces);
    }

    for (std::size_t m = 0; m < kMethods.size(); ++m) {
      const Outcome& o = outcomes[m];
      std::cerr << "[bench]   " << report.name << " " << row.target_faces
                << " faces: " << method_name(kMethods[m], settings.reference_label);
      if (o.available)
        std::cerr << " -> " << o.faces << " faces, H " << o.hausdorff_percent << "%, RMS "
                  << o.rms_percent << "%, " << o.milliseconds << " ms\n";
      else
        std::cerr << " n/a (" << o.note << ")\n";
    }
    report.rows.push_back(std::move(row));
  }
  return report;
}

// --- The report ---

// The machine, date and commit, and how loaded the machine was: the times are one run each
// on a machine shared with other work.
std::string machine_description(const std::string& load_at_start, double total_seconds) {
  std::ostringstream text;
  text << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
       << "- load average (1, 5, 15 min) at the start: " << load_at_start
       << ", at the end: " << command_output("cut -d' ' -f1-3 /proc/loadavg")
       << "; the whole run took " << std::lround(total_seconds) << " s\n"
       << "- peers: meshoptimizer "
       << MESHOPTIMIZER_VERSION / 1000 << "." << MESHOPTIMIZER_VERSION % 1000 / 10 << ", OpenMesh "
       << ((OM_VERSION >> 16) & 0xff) << "." << ((OM_VERSION >> 8) & 0xff) << ", VTK "
       << command_output(
              "/usr/bin/python3 -c 'import vtkmodules.vtkCommonCore as c; "
              "print(c.vtkVersion.GetVTKVersion())' 2>/dev/null || echo missing")
       << "\n";
  return text.str();
}

std::string faces_cell(const Outcome& outcome) {
  if (!outcome.available) return "n/a";
  const std::string faces = with_thousands(outcome.faces);
  return outcome.stalled ? "**stalled at " + faces + "**" : faces;
}

std::string time_cell(Method method, const Outcome& outcome) {
  if (!outcome.available) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", outcome.milliseconds);
  if (method == Method::kPmencSchroederReference || method == Method::kPmencQuadricReference)
    return std::string(text) + " (process, all LODs)";
  return is_pmenc(method) ? std::string(text) + " (all LODs)" : std::string(text);
}

// pm's LOD against a peer's: both errors no larger. "yes: H a / b, RMS c / d" (pm / peer).
struct Comparison {
  bool counted = false;  // a comparison at the same face count was possible
  bool holds = false;
  std::string cell;
};

Comparison compare(const Outcome& ours, const Outcome& peer, const char* peer_short_name) {
  Comparison result;
  if (!peer.available) {
    result.cell = "n/a";
    return result;
  }
  if (peer.stalled) {
    result.cell = std::string(peer_short_name) + " stalled at " + with_thousands(peer.faces);
    return result;
  }
  result.counted = true;
  if (!ours.available || ours.stalled) {
    result.cell = "**no**: pmenc stalled";
    return result;
  }
  result.holds =
      ours.hausdorff_percent <= peer.hausdorff_percent && ours.rms_percent <= peer.rms_percent;
  result.cell = std::string(result.holds ? "yes" : "**no**") + ": H " +
                distinguishable_pair(ours.hausdorff_percent, peer.hausdorff_percent) + ", RMS " +
                distinguishable_pair(ours.rms_percent, peer.rms_percent);
  return result;
}

// --- Issue 25's quality line ---

// Today's pmenc rows against the reference commit's row of the same metric (at most this
// many times its Hausdorff and its RMS) and against meshopt_simplify (at most its Hausdorff
// and its RMS), at every mesh and target.
constexpr double kReferenceTolerance = 1.05;

struct Candidate {
  Method ours;
  Method reference;
};
// Today's one collapse loop, per metric, against the reference's row of the same metric.
constexpr Candidate kCandidates[] = {
    {Method::kPmencQuadric, Method::kPmencQuadricReference},
    {Method::kPmencSchroeder, Method::kPmencSchroederReference}};

// One ratio ours / theirs, three decimals, bold over the limit.
std::string ratio_cell(double ours, double theirs, double limit) {
  char text[32];
  if (theirs > 0)
    std::snprintf(text, sizeof text, "%.3f", ours / theirs);
  else
    std::snprintf(text, sizeof text, "%s", ours > 0 ? "inf" : "1.000");
  return ours > limit * theirs ? "**" + std::string(text) + "**" : std::string(text);
}

// The counts of one candidate over every point.
struct AcceptanceCounts {
  int points = 0;        // points where both comparisons could be made
  int passed = 0;        // ... and both held, on Hausdorff and RMS
  int failed_reference = 0, reference_hausdorff = 0, reference_rms = 0;
  int failed_meshopt = 0, meshopt_hausdorff = 0, meshopt_rms = 0;
  int not_compared = 0;  // a row missing or stalled
};

// One table row: "| mesh | target | H/ref | RMS/ref | H/meshopt | RMS/meshopt | verdict |".
std::string acceptance_row(const MeshReport& report, const TargetRow& row,
                           const Candidate& candidate, AcceptanceCounts& counts) {
  const Outcome& ours = row.outcomes[index_of(candidate.ours)];
  const Outcome& reference = row.outcomes[index_of(candidate.reference)];
  const Outcome& meshopt = row.outcomes[index_of(Method::kMeshopt)];
  std::ostringstream md;
  md << "| " << report.name << " | " << with_thousands(row.target_faces) << " ("
     << significant(100 * row.fraction) << "%) | ";
  auto usable = [](const Outcome& o) { return o.available && !o.stalled; };
  if (!usable(ours) || !usable(reference) || !usable(meshopt)) {
    ++counts.not_compared;
    const char* why = !usable(ours)        ? "this row"
                      : !usable(reference) ? "the reference"
                                           : "meshopt";
    md << "n/a | n/a | n/a | n/a | not compared: " << why << " n/a or stalled |\n";
    return md.str();
  }
  ++counts.points;
  const bool reference_hausdorff =
      ours.hausdorff_percent > kReferenceTolerance * reference.hausdorff_percent;
  const bool reference_rms = ours.rms_percent > kReferenceTolerance * reference.rms_percent;
  const bool meshopt_hausdorff = ours.hausdorff_percent > meshopt.hausdorff_percent;
  const bool meshopt_rms = ours.rms_percent > meshopt.rms_percent;
  counts.reference_hausdorff += reference_hausdorff;
  counts.reference_rms += reference_rms;
  counts.meshopt_hausdorff += meshopt_hausdorff;
  counts.meshopt_rms += meshopt_rms;
  counts.failed_reference += reference_hausdorff || reference_rms;
  counts.failed_meshopt += meshopt_hausdorff || meshopt_rms;
  std::vector<std::string> failures;
  if (reference_hausdorff) failures.push_back("H over the reference's limit");
  if (reference_rms) failures.push_back("RMS over the reference's limit");
  if (meshopt_hausdorff) failures.push_back("H over meshopt's");
  if (meshopt_rms) failures.push_back("RMS over meshopt's");
  md << ratio_cell(ours.hausdorff_percent, reference.hausdorff_percent, kReferenceTolerance)
     << " | " << ratio_cell(ours.rms_percent, reference.rms_percent, kReferenceTolerance) << " | "
     << ratio_cell(ours.hausdorff_percent, meshopt.hausdorff_percent, 1.0) << " | "
     << ratio_cell(ours.rms_percent, meshopt.rms_percent, 1.0) << " | ";
  if (failures.empty()) {
    ++counts.passed;
    md << "yes |\n";
  } else {
    md << "**no**:";
    for (std::size_t i = 0; i < failures.size(); ++i) md << (i ? ", " : " ") << failures[i];
    md << " |\n";
  }
  return md.str();
}

std::string render_one_loop_acceptance(const std::vector<MeshReport>& reports,
                                       const Settings& settings) {
  const std::string& label = settings.reference_label;
  std::ostringstream md, details;
  md << "## Issue 25: against the former default loop of " << label
     << " and meshopt_simplify\n\n"
     << "Issue 25's quality line: at every mesh and target, the one collapse loop's Hausdorff "
        "and RMS each at most "
     << kReferenceTolerance << " times the former default loop's as of commit " << label
     << " (the rows \"pmenc " << label
     << " ...\": that commit's pmenc, built by run_quality.sh, its .pm decoded by today's "
        "library and measured as every other row) and at most meshopt_simplify's. Each metric's "
        "row of today is set against the reference row of the same metric. Cells are ratios "
        "(today / reference, today / meshopt), bold where over the limit ("
     << kReferenceTolerance << " and 1). A point passes when all four hold.\n\n";
  if (settings.reference_pmenc.empty())
    md << "**NOTE: no --reference-pmenc: the reference rows are n/a and no point is "
          "compared.**\n\n";
  md << "| pmenc row | against | points compared | pass | fail against " << label << " x"
     << kReferenceTolerance << " (H, RMS) | fail against meshopt (H, RMS) | not compared |\n"
     << "|---|---|---:|---:|---:|---:|---:|\n";
  for (const Candidate& candidate : kCandidates) {
    AcceptanceCounts counts;
    const std::string ours = method_name(candidate.ours, label);
    details << "### " << ours << "\n\n"
            << "| mesh | target faces | H / " << label << " | RMS / " << label
            << " | H / meshopt | RMS / meshopt | passes |\n"
            << "|---|---:|---:|---:|---:|---:|---|\n";
    for (const MeshReport& report : reports)
      for (const TargetRow& row : report.rows)
        details << acceptance_row(report, row, candidate, counts);
    details << "\n";
    md << "| " << ours << " | " << method_name(candidate.reference, label) << ", meshopt | "
       << counts.points << " | " << counts.passed << " | " << counts.failed_reference << " ("
       << counts.reference_hausdorff << ", " << counts.reference_rms << ") | "
       << counts.failed_meshopt << " (" << counts.meshopt_hausdorff << ", " << counts.meshopt_rms
       << ") | " << counts.not_compared << " |\n";
  }
  md << "\n" << details.str();
  return md.str();
}

std::string render(const std::vector<MeshReport>& reports, const Settings& settings, bool vtk_ran,
                   const std::string& load_at_start, double total_seconds) {
  std::ostringstream md;
  md << "# Quality benchmark\n\n"
     << "Generated by `tests/bench/run_quality.sh` (see tests/bench/README.md for what is "
        "measured and the exact peer settings).\n\n"
     << machine_description(load_at_start, total_seconds) << "\n"
     << "Errors: Hausdorff and RMS distance between the LOD and the input, both ways, by "
        "`pm::measure_surface_distance` (Metro-style sampling, 10 samples per face and every "
        "vertex), in percent of the input's bounding-box diagonal; the same code for every "
        "method. Faces reached: the LOD's face count; **stalled at N** when a method ends more "
        "than "
     << static_cast<int>(kStallTolerance * 100)
     << "% above the target. Time: milliseconds, one run, on a shared machine. **pmenc's time "
        "is one `pm::encode` that produces the whole sequence of LODs**, down to its base "
        "mesh, and is the same for every target; each peer's time produces one LOD. "
        "OpenMesh's time is the decimater's setup and decimation (not building its mesh); "
        "vtkDecimatePro's is its `Update()` alone.\n\n"
     << "pmenc's rows, per metric: the one collapse loop (since issue 25; `pm::encode` with "
        "its measured distance, pmenc's default below a million faces; `pmenc --fast` leaves "
        "the measure out, tests/bench/fast_unmeasured.md), and **pmenc "
     << settings.reference_label << "**: the former default loop (OpenMesh half-edge mesh, "
        "deleted by issue 25) as of commit "
     << settings.reference_label
     << ", issue 25's reference, whose pmenc run_quality.sh builds from that commit's sources "
        "and runs as a process (`--drop-attributes --fast-from 0 --metric M`, the rest at its "
        "defaults); its .pm is decoded by today's library and its levels taken and measured "
        "as the others' (its time is the whole process: reading, encoding, writing). The "
        "section \"Issue 25\" below sets today's rows against it and against "
        "meshopt_simplify.\n\n"
     << "pmenc encodes geometry only here (`EncodeOptions::drop_attributes`), as every peer is "
        "given positions and triangles only. With texture coordinates on both sides, pmenc "
        "against meshopt_simplify on a seam-split vertex buffer: [uv.md](uv.md) (UV error at "
        "10% and 2%, regenerated by `tests/bench/run_uv.sh`, which this command also runs).\n\n";

  for (const MeshReport& report : reports) {
    md << "## " << report.name << "\n\n"
       << with_thousands(report.faces) << " faces, " << with_thousands(report.vertices)
       << " vertices, diagonal " << significant(report.diagonal) << ". pmenc encode:";
    for (const Method method : kMethods)
      if (is_pmenc(method))
        md << (method == kMethods.front() ? " " : ", ")
           << method_name(method, settings.reference_label).substr(std::strlen("pmenc ")) << " "
           << std::lround(report.encode_ms[index_of(method)]) << " ms";
    md << ".";
    if (!report.repairs.empty()) md << " pmenc repaired: " << report.repairs << ".";
    if (report.openmesh_refused_faces > 0)
      md << " OpenMesh refused " << report.openmesh_refused_faces
         << " faces as complex; they were added with their own vertex copies.";
    md << "\n\n| mesh | target faces | method | faces reached | Hausdorff % | RMS % | time ms |\n"
       << "|---|---:|---|---:|---:|---:|---:|\n";
    for (const TargetRow& row : report.rows) {
      for (std::size_t m = 0; m < kMethods.size(); ++m) {
        const Outcome& o = row.outcomes[m];
        md << "| " << report.name << " | " << with_thousands(row.target_faces) << " ("
           << significant(100 * row.fraction) << "%) | "
           << method_name(kMethods[m], settings.reference_label) << " | "
           << faces_cell(o) << " | "
           << (o.available ? significant(o.hausdorff_percent) : std::string("n/a")) << " | "
           << (o.available ? significant(o.rms_percent) : std::string("n/a")) << " | "
           << time_cell(kMethods[m], o) << " |\n";
      }
    }
    md << "\n";
  }

  md << render_one_loop_acceptance(reports, settings);

  // The acceptance comparisons of issue 3, at the same face count, then two more that are
  // not part of it: against the OpenMesh variant, and against vtk at the count where it stalled.
  md << "## Summary (issue 3)\n\n"
     << "Does pm's LOD measure no larger than the peer's, on both Hausdorff and RMS? Cells read "
        "\"H pm / peer, RMS pm / peer\" in percent of the diagonal. The first three columns are "
        "issue 3's acceptance comparisons: pmenc quadric against meshopt_simplify and OpenMesh "
        "ModQuadric, pmenc schroeder against vtkDecimatePro where vtk reaches the target. The "
        "other two are extra, counted apart: pmenc quadric against the OpenMesh variant with "
        "the normal-flip guard; and, where vtk stalls, pmenc schroeder measured at vtk's face "
        "count.\n\n"
     << "| mesh | target faces | quadric <= meshopt | quadric <= OpenMesh | schroeder <= vtk | "
        "extra: quadric <= OpenMesh+NormalFlipping | extra: schroeder <= vtk at vtk's count |\n"
     << "|---|---:|---|---|---|---|---|\n";
  constexpr std::size_t kColumns = 5, kAcceptanceColumns = 3;
  const char* const column_names[kColumns] = {"quadric <= meshopt",
                                              "quadric <= OpenMesh",
                                              "schroeder <= vtk",
                                              "quadric <= OpenMesh+NormalFlipping",
                                              "schroeder <= vtk at vtk's stalled count"};
  std::array<int, kColumns> held{}, counted{};
  for (const MeshReport& report : reports) {
    for (const TargetRow& row : report.rows) {
      const auto& o = row.outcomes;
      const Outcome& schroeder = o[index_of(Method::kPmencSchroeder)];
      const Outcome& quadric = o[index_of(Method::kPmencQuadric)];
      const Outcome& vtk = o[index_of(Method::kVtk)];
      std::array<Comparison, kColumns> cells = {
          compare(quadric, o[index_of(Method::kMeshopt)], "meshopt"),
          compare(quadric, o[index_of(Method::kOpenMesh)], "OpenMesh"),
          compare(schroeder, vtk, "vtk"),
          compare(quadric, o[index_of(Method::kOpenMeshNormalFlipping)], "OpenMesh"),
          {}};
      if (row.schroeder_at_vtk_faces) {
        Outcome vtk_at_own_count = vtk;
        vtk_at_own_count.stalled = false;  // compared at the face count it reached
        cells[4] = compare(*row.schroeder_at_vtk_faces, vtk_at_own_count, "vtk");
        cells[4].cell = "at " + with_thousands(vtk.faces) + " (pm " +
                        with_thousands(row.schroeder_at_vtk_faces->faces) + "): " + cells[4].cell;
      }
      md << "| " << report.name << " | " << with_thousands(row.target_faces);
      for (std::size_t c = 0; c < kColumns; ++c) {
        md << " | " << cells[c].cell;
        counted[c] += cells[c].counted;
        held[c] += cells[c].holds;
      }
      md << " |\n";
    }
  }
  int acceptance_held = 0, acceptance_counted = 0;
  for (std::size_t c = 0; c < kAcceptanceColumns; ++c) {
    acceptance_held += held[c];
    acceptance_counted += counted[c];
  }
  md << "\n**" << acceptance_held << " of " << acceptance_counted
     << " acceptance comparisons hold** (a peer that stalls gives no comparison at the "
        "target).\n\n";
  for (std::size_t c = 0; c < kColumns; ++c)
    md << "- " << (c >= kAcceptanceColumns ? "extra, " : "") << column_names[c] << ": " << held[c]
       << " of " << counted[c] << "\n";
  if (!settings.use_vtk)
    md << "\n**NOTE: vtkDecimatePro was left out (--no-vtk).**\n";
  else if (!vtk_ran)
    md << "\n**NOTE: VTK's Python modules were missing: the vtkDecimatePro column is n/a.**\n";
  return md.str();
}

// --- Command line ---

const char kUsage[] =
    "usage: pm_bench_quality [MESH_OR_DIRECTORY...] [--targets 0.5,0.1,0.02] [--out FILE]\n"
    "                        [--no-vtk] [--vtk-script PATH] [--dump DIRECTORY]\n"
    "                        [--reference-pmenc PATH] [--reference-label NAME]\n"
    "Simplifies each mesh (default: ../shared/meshes next to the repository) to each target\n"
    "fraction of its faces with pmenc schroeder and quadric (each also with the pmenc of\n"
    "--reference-pmenc, rows named after --reference-label), meshopt_simplify,\n"
    "OpenMesh's Decimater (ModQuadric) and vtkDecimatePro, measures every LOD with the same\n"
    "code, and prints a markdown report (also written to FILE with --out). Progress goes to\n"
    "stderr. --dump writes every LOD to DIRECTORY as OBJ.\n";

bool parse_arguments(int argc, char** argv, Settings& settings) {
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    const bool has_value = i + 1 < argc;
    if (argument == "--help" || argument == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (argument == "--targets" && has_value) {
      if (!pm::bench::parse_targets(argv[++i], settings.targets)) {
        std::cerr << "pm_bench_quality: --targets wants fractions in (0, 1], e.g. 0.5,0.1\n";
        return false;
      }
    } else if (argument == "--out" && has_value) {
      settings.out_path = argv[++i];
    } else if (argument == "--vtk-script" && has_value) {
      settings.vtk_script = argv[++i];
    } else if (argument == "--dump" && has_value) {
      settings.dump_directory = argv[++i];
      fs::create_directories(settings.dump_directory);
    } else if (argument == "--reference-pmenc" && has_value) {
      settings.reference_pmenc = argv[++i];
    } else if (argument == "--reference-label" && has_value) {
      settings.reference_label = argv[++i];
    } else if (argument == "--no-vtk") {
      settings.use_vtk = false;
    } else if (!argument.empty() && argument[0] == '-') {
      std::cerr << "pm_bench_quality: unknown or incomplete option " << argument << "\n" << kUsage;
      return false;
    } else {
      settings.inputs.push_back(argument);
    }
  }
  if (settings.inputs.empty())
    settings.inputs.push_back(std::string(PM_BENCH_SOURCE_DIR) + "/../shared/meshes");
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (!parse_arguments(argc, argv, settings)) return 2;
  const std::vector<fs::path> files = pm::bench::mesh_files(settings.inputs);
  if (files.empty()) {
    std::cerr << "\n*** NOTE: no meshes to benchmark (looked in";
    for (const std::string& input : settings.inputs) std::cerr << " " << input;
    std::cerr << "). Nothing measured.\n\n";
    return 3;
  }

  const std::string load_at_start = command_output("cut -d' ' -f1-3 /proc/loadavg");
  const auto start = Clock::now();
  const fs::path scratch =
      fs::temp_directory_path() / ("pm_bench_quality." + std::to_string(getpid()));
  fs::create_directories(scratch);
  bool vtk_available = settings.use_vtk;
  if (!settings.use_vtk) std::cerr << "\n*** NOTE: --no-vtk: the vtkDecimatePro column is n/a.\n\n";

  std::vector<MeshReport> reports;
  for (const fs::path& file : files)
    if (auto report = run_mesh(file, settings, scratch, vtk_available))
      reports.push_back(std::move(*report));
  std::error_code ignored;
  fs::remove_all(scratch, ignored);

  const std::string markdown = render(reports, settings, vtk_available, load_at_start,
                                      milliseconds_since(start) / 1000);
  std::cout << markdown;
  if (!settings.out_path.empty()) {
    std::ofstream out(settings.out_path, std::ios::binary);
    out << markdown;
    if (!out) {
      std::cerr << "pm_bench_quality: cannot write " << settings.out_path << "\n";
      return 5;
    }
  }
  return reports.size() == files.size() ? 0 : 1;
}
