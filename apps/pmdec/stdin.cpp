// pmdec --stdin [--every N]: levels written while the stream arrives.
#include <cstdio>
#include <iostream>
#include <string_view>

#include "cli_common.h"
#include "pm/lod.h"
#include "pmdec/pmdec.h"

namespace pmdec {

// pmdec --stdin [--every N]: the stream decoded as it arrives (Hoppe 1996, §3, progressive
// transmission), a level written each time N more faces have arrived, and the finest level
// at the end.
int decode_progressively(const Settings& settings, uint64_t every, const std::string& output,
                         bool quiet) {
  const std::string input = "(stdin)";
  pm::ReadOptions options = settings.read;
  options.allow_truncated = true;
  pm::PmStreamReader reader(options);
  const auto write_level = [&](uint64_t name_faces, std::size_t level) {
    pm::Mesh mesh = pm::extract_level(reader.mesh(), level);
    group_materials_for_output(reader.mesh(), true, level, mesh);
    std::string path = output;
    path.replace(path.find("{faces}"), 7, std::to_string(name_faces));
    const pm::MeshFormat format = output_format_for(path, settings.output_format);
    bool output_failed = false;
    const pm::Status s = pm::cli::write_mesh_output(mesh, format, path,
                                                    settings.create_directories, &output_failed);
    if (!s) {
      const int code = pm::cli::fail(kTool, path, s);
      return output_failed ? static_cast<int>(pm::cli::exit_code_for_write(s)) : code;
    }
    if (!quiet)
      std::cerr << kTool << ": " << path << ": level " << level << ", " << mesh.face_count()
                << " faces\n";
    return static_cast<int>(pm::cli::kExitOk);
  };
  uint64_t next = every;
  std::vector<char> buffer(1 << 16);
  for (;;) {
    const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), stdin);
    if (n == 0) break;
    if (pm::Status s = reader.append(std::string_view(buffer.data(), n)); !s)
      return pm::cli::fail(kTool, input, s);
    while (every != 0 && reader.has_base() && reader.decoded_face_count() >= next) {
      const pm::ProgressiveMesh& mesh = reader.mesh();
      if (const int code = write_level(next, pm::level_for_faces(mesh, next)); code != 0)
        return code;
      next += every;
    }
  }
  if (std::ferror(stdin)) {
    return pm::cli::fail(kTool, input,
                         pm::Status(pm::ErrorCode::kIoError, "cannot read standard input"));
  }
  pm::ReadResult result;
  if (pm::Status s = reader.finish(&result); !s) return pm::cli::fail(kTool, input, s);
  if (result.truncated && !quiet)
    std::cerr << kTool << ": " << input << ": warning: " << result.warning << "\n";
  const pm::ProgressiveMesh& mesh = reader.mesh();
  if (const int code = write_level(reader.decoded_face_count(), mesh.splits.size()); code != 0)
    return code;
  return result.truncated ? pm::cli::kExitTruncated : pm::cli::kExitOk;
}

}  // namespace pmdec
