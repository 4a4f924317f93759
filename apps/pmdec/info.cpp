// pmdec --info [--sizes]: a .pm file's header, counts, attributes and error range, read
// from its header and index without decoding (pm::read_pm_info); --sizes decodes it to say
// where the bytes go.
#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "pm/advanced/pm_stream.h"
#include "pmdec/pmdec.h"

namespace pmdec {

namespace {

// --sizes: where the bytes go (pm::measure_pm_sizes), the chunk streams in bits per split.
int print_sizes(const std::string& input, const std::string& bytes, uint32_t splits,
                const pm::ReadOptions& read_options) {
  pm::PmSizes sizes;
  if (pm::Status s = pm::measure_pm_sizes(bytes, sizes, read_options); !s)
    return pm::cli::fail(kTool, input, s);
  std::string sections = "header " + std::to_string(sizes.header) + " B";
  for (const auto& [tag, size] : sizes.sections) {
    sections += ", " + tag + " " + std::to_string(size) + " B";
    if (tag == "CHNK") sections += " (" + std::to_string(sizes.chunks) + " chunks)";
  }
  std::printf("sections:         %s\n", sections.c_str());
  if (splits == 0) return pm::cli::kExitOk;
  // Each stream compressed alone: about what it costs in the file.
  std::string streams;
  for (std::size_t k = 0; k < sizes.chunk_streams.size(); ++k) {
    if (sizes.chunk_streams[k].second == 0) continue;
    char text[96];
    std::snprintf(text, sizeof text, "%s%s %.2f", streams.empty() ? "" : ", ",
                  sizes.chunk_streams[k].first.c_str(),
                  8.0 * double(sizes.chunk_streams_compressed[k]) / double(splits));
    streams += text;
  }
  std::printf("chunk streams:    bits per split, each alone with zstd -19: %s\n", streams.c_str());
  return pm::cli::kExitOk;
}

int print_info(const std::string& input, const pm::ReadOptions& read_options, bool with_sizes) {
  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes, read_options.max_memory); !s)
    return pm::cli::fail(kTool, input, s);
  pm::PmInfo info;
  if (pm::Status s = pm::read_pm_info(bytes, info); !s) return pm::cli::fail(kTool, input, s);
  std::printf("file:             %s (%zu bytes)\n", input.c_str(), bytes.size());
  std::printf("format version:   %u.%u\n", info.major, info.minor);
  std::string attributes;
  auto add = [&attributes](const std::string& item) {
    attributes += (attributes.empty() ? "" : "; ") + item;
  };
  if (info.color_components) add(info.color_components == 4 ? "colours (rgba)" : "colours (rgb)");
  if (info.uv_count || info.has_uvs)
    add(std::to_string(info.uv_count) + " texture coordinates" +
        (info.has_uvs ? " per corner" : " (table only)"));
  if (info.normal_count || info.has_normals)
    add(std::to_string(info.normal_count) + " normals" +
        (info.has_normals ? " per corner" : " (table only)"));
  if (info.material_count || info.has_materials)
    add(std::to_string(info.material_count) + " materials" +
        (info.has_materials ? " per face" : " (table only)"));
  if (info.material_library_count)
    add(std::to_string(info.material_library_count) + " material " +
        (info.material_library_count == 1 ? "library" : "libraries"));
  std::printf("flags:            0x%08x\n", info.flags);
  std::printf("attributes:       %s\n", attributes.empty() ? "none" : attributes.c_str());
  std::printf("base mesh:        %u vertices, %u faces\n", info.base_vertex_count,
              info.base_face_count);
  std::printf("vertex splits:    %u\n", info.split_count);
  std::printf("full detail:      %llu vertices, %llu faces\n",
              static_cast<unsigned long long>(info.full_vertex_count),
              static_cast<unsigned long long>(info.full_face_count));
  std::printf(
      "repairs carried:  %u welded vertices, %u faces with a repeated vertex, %u unreferenced "
      "vertices\n",
      info.weld_count, info.carried_face_count, info.loose_vertex_count);
  std::printf("error range:      0 (full detail) to %.9g (base mesh), model units\n",
              info.max_error);
  if (info.major >= 2) {
    const auto bits = [](uint32_t b) {
      return b == 0 ? std::string("lossless") : std::to_string(b) + " bits";
    };
    // 2.3: lossless positions on the grid of their decimals.
    const std::string positions =
        info.positions_decimal
            ? "lossless (decimals, a " + std::to_string(info.position_bits) + "-bit grid)"
        : info.positions_significant
            ? std::string("lossless (decimals of a few significant digits)")
            : bits(info.position_bits);
    const auto table = [&](uint32_t b, bool significant) {
      return significant ? std::string("lossless (decimals of a few significant digits)") : bits(b);
    };
    std::printf("quantization:     positions %s, texture coordinates %s, normals %s\n",
                positions.c_str(), table(info.uv_bits, info.uvs_significant).c_str(),
                table(info.normal_bits, info.normals_significant).c_str());
    // The index: what a reader decompresses for a level (pm-format.md §5.6).
    std::printf("chunks:           %zu", info.chunks.size());
    if (!info.chunks.empty()) {
      const pm::PmInfo::Chunk& first = info.chunks.front();
      std::printf(" (the first: %u splits, %llu faces after it, ending at byte %llu)", first.splits,
                  static_cast<unsigned long long>(first.faces_after),
                  static_cast<unsigned long long>(first.stream_end));
    }
    std::printf("\n");
  }
  if (with_sizes) return print_sizes(input, bytes, info.split_count, read_options);
  return pm::cli::kExitOk;
}
}  // namespace

int print_infos(const pm::cli::BatchCommandLine& command, const pm::ReadOptions& read_options,
                bool with_sizes) {
  std::vector<pm::cli::Input> inputs;
  pm::cli::InputOptions input_options{command.inputs, command.lists, command.recursive, {"pm"}};
  if (pm::Status s = pm::cli::gather_inputs(input_options, inputs); !s) {
    std::cerr << kTool << ": " << s.message() << "\n";
    return pm::cli::exit_code_for(s.code());
  }
  int exit_code = pm::cli::kExitOk;
  std::size_t failures = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (i > 0) std::printf("\n");
    exit_code = inputs[i].problem ? print_info(inputs[i].path, read_options, with_sizes)
                                  : pm::cli::fail(kTool, inputs[i].path, inputs[i].problem);
    if (exit_code != pm::cli::kExitOk) ++failures;
  }
  if (inputs.size() == 1) return exit_code;
  return failures ? pm::cli::kExitSomeFailed : pm::cli::kExitOk;
}

}  // namespace pmdec
