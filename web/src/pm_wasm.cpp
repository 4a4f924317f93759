// The decoder's C interface for WebAssembly (web/pm-core.js calls it through the module's
// exports). It wraps pm::codec as it is, with no second reading of the format: a stream
// reader that takes bytes as they arrive, levels as extract_level() writes them (what pmdec
// writes), and the runtime (RuntimeLod) and its geomorphs, whose wedge arrays a renderer
// uploads as they are.
//
// Why a plain C interface rather than embind: the arrays stay in the module's memory and JS
// reads them through views of it (a descriptor of pointers and lengths, below), with no copy
// on this side; there is no per-call marshalling code to ship (embind adds tens of KB); and
// every entry point can be written so that nothing escapes: each catches every C++
// exception and returns a pm::ErrorCode number, with the message kept for pmw_error_message.
// (A trap, which C++ cannot catch, is handled on the JS side: pm-core.js turns it into an
// Error of code "internal" and refuses further calls on that decoder's module.)
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/pm_codec.h"

#define PMW_EXPORT extern "C" __attribute__((used, visibility("default")))

namespace {

// How a level is asked for (the JS API's request kinds, in this order).
enum class LevelBy : int { kLevel = 0, kFaces = 1, kVertices = 2, kError = 3, kRatio = 4 };

struct Decoder {
  explicit Decoder(const pm::ReadOptions& options) : reader(options) {}
  pm::PmStreamReader reader;
  pm::Status stream_status;  // the stream's first error, which is final
  pm::ErrorCode code = pm::ErrorCode::kOk;  // the last error's
  std::string message;
  pm::Mesh level;       // the last level extracted
  std::vector<uint32_t> descriptor;
  // The runtime over the splits decoded when it was built; rebuilt when more have arrived.
  std::unique_ptr<pm::RuntimeLod> runtime;
  std::size_t runtime_splits = 0;
  std::optional<pm::RuntimeLod::Geomorph> geomorph;
  std::vector<float> morph_positions, morph_uvs, morph_normals, morph_colors;
};

int fail(Decoder* decoder, pm::ErrorCode code, std::string message) {
  decoder->code = code;
  decoder->message = std::move(message);
  return static_cast<int>(code);
}

int report(Decoder* decoder, const pm::Status& status) {
  if (status.is_ok()) return 0;
  return fail(decoder, status.code(), status.message());
}

// Runs `body` (returning an ErrorCode number) with every exception turned into a code: the
// module is built with exceptions enabled so that these catch what the library throws
// (allocation failure is kResourceLimit, as read_pm reports it).
template <typename Body>
int guarded(Decoder* decoder, Body&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(decoder, pm::ErrorCode::kResourceLimit, "out of memory");
  } catch (const std::exception& error) {
    return fail(decoder, pm::ErrorCode::kInternal, error.what());
  } catch (...) {
    return fail(decoder, pm::ErrorCode::kInternal, "unknown exception");
  }
}

uint32_t address(const void* pointer) {
  return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(pointer));
}

template <typename T>
void describe(std::vector<uint32_t>& out, const std::vector<T>& values) {
  out.push_back(values.empty() ? 0 : address(values.data()));
  out.push_back(static_cast<uint32_t>(values.size()));
}

std::size_t level_for(const pm::ProgressiveMesh& mesh, LevelBy by, double value) {
  switch (by) {
    case LevelBy::kFaces: return pm::level_for_faces(mesh, value < 0 ? 0 : std::size_t(value));
    case LevelBy::kVertices:
      return pm::level_for_vertices(mesh, value < 0 ? 0 : std::size_t(value));
    case LevelBy::kError: return pm::level_for_error(mesh, value);
    case LevelBy::kRatio: {
      const double full = double(pm::faces_at_level(mesh, mesh.split_count()));
      const double faces = value * full + 0.5;
      return pm::level_for_faces(mesh, faces < 0 ? 0 : std::size_t(faces));
    }
    case LevelBy::kLevel:
    default: return value < 0 ? 0 : std::size_t(value) > mesh.split_count() ? mesh.split_count()
                                                                            : std::size_t(value);
  }
}

int check_request(Decoder* decoder, int by, double value) {
  if (!decoder->stream_status.is_ok()) return report(decoder, decoder->stream_status);
  if (!decoder->reader.has_base()) {
    return fail(decoder, pm::ErrorCode::kInvalidArgument, "no level yet: the base mesh has not arrived");
  }
  if (by < 0 || by > 4 || value != value) {
    return fail(decoder, pm::ErrorCode::kInvalidArgument, "a level request must be a number of a known kind");
  }
  return 0;
}

// The runtime for the splits decoded so far: RuntimeLod copies the progressive mesh, so it
// is rebuilt only when chunks have arrived since.
void update_runtime(Decoder* decoder) {
  const pm::ProgressiveMesh& mesh = decoder->reader.mesh();
  if (decoder->runtime && decoder->runtime_splits == mesh.split_count()) return;
  decoder->geomorph.reset();  // it points into the runtime it came from
  decoder->runtime.reset();
  decoder->runtime = std::make_unique<pm::RuntimeLod>(mesh);
  decoder->runtime_splits = mesh.split_count();
}

}  // namespace

PMW_EXPORT Decoder* pmw_create(double max_memory, int allow_truncated) {
  try {
    pm::ReadOptions options;
    options.max_memory = max_memory > 0 ? uint64_t(max_memory) : 0;
    options.allow_truncated = allow_truncated != 0;
    return new Decoder(options);
  } catch (...) {
    return nullptr;
  }
}

PMW_EXPORT void pmw_destroy(Decoder* decoder) { delete decoder; }

// The last error (a call that returns an address returns 0 on error, without its code).
PMW_EXPORT int pmw_error_code(Decoder* decoder) { return static_cast<int>(decoder->code); }
PMW_EXPORT const char* pmw_error_message(Decoder* decoder) { return decoder->message.c_str(); }

PMW_EXPORT int pmw_append(Decoder* decoder, const char* bytes, std::size_t size) {
  return guarded(decoder, [&] {
    if (decoder->stream_status.is_ok()) decoder->stream_status = decoder->reader.append({bytes, size});
    return report(decoder, decoder->stream_status);
  });
}

PMW_EXPORT int pmw_finish(Decoder* decoder) {
  return guarded(decoder, [&] {
    if (decoder->stream_status.is_ok()) decoder->stream_status = decoder->reader.finish();
    return report(decoder, decoder->stream_status);
  });
}

// The stream's state, as doubles (counts reach past 2^31): has base, complete, faces of the
// finest level decoded, faces of the whole stream (0 before the header), splits decoded.
PMW_EXPORT double pmw_state(Decoder* decoder, int field) {
  switch (field) {
    case 0: return decoder->reader.has_base();
    case 1: return decoder->reader.complete();
    case 2: return double(decoder->reader.decoded_face_count());
    case 3: return double(decoder->reader.stream_face_count());
    case 4: return decoder->reader.has_base() ? double(decoder->reader.mesh().split_count()) : 0;
    default: return 0;
  }
}

// Extracts a level (extract_level: welded copies merged, faces grouped by material: what pmdec writes)
// and returns the address of its descriptor, or 0 on error (pmw_error_message). Descriptor,
// u32 each: level, split count, faces, vertices, colour components, error bound (f32 bits),
// then (address, length in elements) of positions, triangles, colours, uvs, uv indices,
// normals, normal indices, face materials.
PMW_EXPORT uint32_t pmw_level(Decoder* decoder, int by, double value) {
  const int code = guarded(decoder, [&] {
    if (int bad = check_request(decoder, by, value)) return bad;
    const pm::ProgressiveMesh& mesh = decoder->reader.mesh();
    const std::size_t level = level_for(mesh, LevelBy(by), value);
    decoder->level = pm::Mesh();
    decoder->level = pm::extract_level(mesh, level);
    // Each material's faces together (one draw call, one three.js group each), as pmdec
    // writes a level; full detail of a stream that keeps the input's order keeps it.
    if (!(mesh.keeps_order() && level == mesh.split_count())) {
      pm::group_faces_by_material(decoder->level);
    }
    const pm::Mesh& out = decoder->level;
    const float error = pm::error_at_level(mesh, level);
    uint32_t error_bits;
    static_assert(sizeof error_bits == sizeof error);
    __builtin_memcpy(&error_bits, &error, sizeof error);
    std::vector<uint32_t>& d = decoder->descriptor;
    d = {uint32_t(level), uint32_t(mesh.split_count()), uint32_t(out.face_count()),
         uint32_t(out.vertex_count()), out.color_components, error_bits};
    describe(d, out.positions);
    describe(d, out.triangles);
    describe(d, out.colors);
    describe(d, out.uvs);
    describe(d, out.uv_indices);
    describe(d, out.normals);
    describe(d, out.normal_indices);
    describe(d, out.face_materials);
    return 0;
  });
  return code == 0 ? address(decoder->descriptor.data()) : 0;
}

// Sets the runtime (built over the splits decoded so far) to a level and returns its
// descriptor, or 0 on error. u32 each: level, max level, faces, wedges in use, colour
// components, error bound (f32 bits), then addresses of the index buffer (3 per face, the
// active faces first), wedge positions (3 per wedge), uvs (2), normals (3), colours (or 0).
PMW_EXPORT uint32_t pmw_runtime(Decoder* decoder, int by, double value) {
  const int code = guarded(decoder, [&] {
    if (int bad = check_request(decoder, by, value)) return bad;
    update_runtime(decoder);
    pm::RuntimeLod& runtime = *decoder->runtime;
    const std::size_t level = level_for(decoder->reader.mesh(), LevelBy(by), value);
    runtime.set_level(level);
    const float error = pm::error_at_level(decoder->reader.mesh(), level);
    uint32_t error_bits;
    __builtin_memcpy(&error_bits, &error, sizeof error);
    decoder->descriptor = {uint32_t(runtime.level()), uint32_t(runtime.max_level()),
                           uint32_t(runtime.face_count()), uint32_t(runtime.wedge_count()),
                           runtime.color_components(), error_bits,
                           address(runtime.indices()), address(runtime.positions()),
                           address(runtime.uvs()), address(runtime.normals()),
                           address(runtime.colors())};
    return 0;
  });
  return code == 0 ? address(decoder->descriptor.data()) : 0;
}

// A geomorph (Hoppe 1996, §4.2) between two levels of the runtime (each requested as in
// pmw_runtime; from is clamped to at most to), left at level `to`. Returns its descriptor or
// 0: from level, to level, faces, wedges, colour components, has uvs, has normals, address
// of its index buffer.
PMW_EXPORT uint32_t pmw_geomorph(Decoder* decoder, int by, double from_value, double to_value) {
  const int code = guarded(decoder, [&] {
    if (int bad = check_request(decoder, by, from_value)) return bad;
    if (int bad = check_request(decoder, by, to_value)) return bad;
    update_runtime(decoder);
    const pm::ProgressiveMesh& mesh = decoder->reader.mesh();
    const std::size_t to = level_for(mesh, LevelBy(by), to_value);
    std::size_t from = level_for(mesh, LevelBy(by), from_value);
    if (from > to) from = to;
    decoder->geomorph.reset();
    decoder->geomorph.emplace(decoder->runtime->geomorph(from, to));
    const pm::RuntimeLod& runtime = *decoder->runtime;
    const pm::RuntimeLod::Geomorph& morph = *decoder->geomorph;
    decoder->descriptor = {uint32_t(from), uint32_t(to), uint32_t(morph.face_count()),
                           uint32_t(morph.wedge_count()), runtime.color_components(),
                           runtime.uvs() != nullptr, runtime.normals() != nullptr,
                           address(morph.indices())};
    return 0;
  });
  return code == 0 ? address(decoder->descriptor.data()) : 0;
}

// Blends the last geomorph at alpha into arrays held here; returns the address of four u32:
// positions, uvs, normals, colours (0 where the mesh has none), or 0 on error.
PMW_EXPORT uint32_t pmw_geomorph_evaluate(Decoder* decoder, float alpha) {
  const int code = guarded(decoder, [&] {
    if (!decoder->geomorph) {
      return fail(decoder, pm::ErrorCode::kInvalidArgument, "no geomorph: ask for one first");
    }
    const pm::RuntimeLod& runtime = *decoder->runtime;
    const pm::RuntimeLod::Geomorph& morph = *decoder->geomorph;
    const std::size_t wedges = morph.wedge_count();
    decoder->morph_positions.resize(3 * wedges);
    decoder->morph_uvs.resize(runtime.uvs() ? 2 * wedges : 0);
    decoder->morph_normals.resize(runtime.normals() ? 3 * wedges : 0);
    decoder->morph_colors.resize(runtime.colors() ? runtime.color_components() * wedges : 0);
    auto or_null = [](std::vector<float>& v) { return v.empty() ? nullptr : v.data(); };
    morph.evaluate(alpha < 0 ? 0 : alpha > 1 ? 1 : alpha, decoder->morph_positions.data(),
                   or_null(decoder->morph_uvs), or_null(decoder->morph_normals),
                   or_null(decoder->morph_colors));
    decoder->descriptor = {address(or_null(decoder->morph_positions)),
                           address(or_null(decoder->morph_uvs)),
                           address(or_null(decoder->morph_normals)),
                           address(or_null(decoder->morph_colors))};
    return 0;
  });
  return code == 0 ? address(decoder->descriptor.data()) : 0;
}

// The stable name of an error code ("corrupt-stream"), as the CLI's --json prints it.
PMW_EXPORT const char* pmw_error_code_name(int code) {
  return pm::error_code_name(static_cast<pm::ErrorCode>(code));
}
