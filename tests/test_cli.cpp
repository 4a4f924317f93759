// pmenc and pmdec end to end, as a user runs them: files in, files out, exit codes, and
// nothing left behind on failure.
#include <dirent.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "test_meshes.h"
#include "test_util.h"

namespace pm {
namespace {

using test::CommandResult;
using test::run_command;
using test::TempDir;

CommandResult pmenc(std::vector<std::string> args) {
  args.insert(args.begin(), PMENC_PATH);
  return run_command(args);
}
CommandResult pmdec(std::vector<std::string> args) {
  args.insert(args.begin(), PMDEC_PATH);
  return run_command(args);
}

Mesh read_or_fail(const std::string& path) {
  Mesh mesh;
  Status s = read_mesh(path, mesh);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  return mesh;
}

// The directory holds exactly these names (no temporary or partial file).
std::vector<std::string> listing(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* entry = readdir(d))
      if (entry->d_name[0] != '.') names.push_back(entry->d_name);
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// stderr is one line: "tool: FILE: message".
void expect_one_line_error(const CommandResult& r, const std::string& tool,
                           const std::string& file) {
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.err.rfind(tool + ": " + file + ": ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

class EndToEnd : public ::testing::TestWithParam<test::TestMesh> {};

TEST_P(EndToEnd, FullDetailRoundTripIsExact) {
  PM_SKIP_IF_MISSING(GetParam());
  TempDir dir;
  const CommandResult enc = pmenc({GetParam().path, "-o", dir.file("x.pm"), "-q"});
  ASSERT_EQ(enc.exit_code, 0) << enc.err;
  EXPECT_EQ(enc.err, "");
  const CommandResult dec = pmdec({dir.file("x.pm"), "-o", dir.file("full.obj"), "-q"});
  ASSERT_EQ(dec.exit_code, 0) << dec.err;
  const Mesh input = read_or_fail(GetParam().path);
  const Mesh full = read_or_fail(dir.file("full.obj"));
  EXPECT_TRUE(test::same_faces(input, full));
  EXPECT_EQ(full.vertex_count(), input.vertex_count());
}

TEST_P(EndToEnd, FacesAndRatioRequestsAreHonoured) {
  PM_SKIP_IF_MISSING(GetParam());
  TempDir dir;
  ASSERT_EQ(pmenc({GetParam().path, "-o", dir.file("x.pm"), "-q"}).exit_code, 0);
  const Mesh input = read_or_fail(GetParam().path);
  const std::size_t full = input.face_count();
  // Requests are honoured from the base mesh's faces up (below it, the base is given).
  ASSERT_EQ(pmdec({dir.file("x.pm"), "--faces", "0", "-o", dir.file("b.obj"), "-q"}).exit_code, 0);
  const std::size_t base = read_or_fail(dir.file("b.obj")).face_count();
  for (std::size_t n : {full / 2, full / 10 + 1, full / 5, base, base + 1, full - 1}) {
    n = std::max(n, base);
    const CommandResult r =
        pmdec({dir.file("x.pm"), "--faces", std::to_string(n), "-o", dir.file("l.obj"), "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::size_t got = read_or_fail(dir.file("l.obj")).face_count();
    EXPECT_TRUE(got == n || got == n + 1) << "asked " << n << ", got " << got;
  }
  const CommandResult r =
      pmdec({dir.file("x.pm"), "--ratio", "0.1", "-o", dir.file("r.ply"), "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t want = std::max(base, static_cast<std::size_t>(std::llround(0.1 * full)));
  const std::size_t got = read_or_fail(dir.file("r.ply")).face_count();
  EXPECT_TRUE(got == want || got == want + 1) << "want " << want << ", got " << got;
}

INSTANTIATE_TEST_SUITE_P(Meshes, EndToEnd, ::testing::ValuesIn(test::all_test_meshes()),
                         test::test_mesh_name);

TEST(Cli, EveryOutputFormatDecodesTheSameFaces) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("terrain_holes.obj");
  ASSERT_EQ(pmenc({input, "-o", dir.file("t.pm"), "-q"}).exit_code, 0);
  const Mesh original = read_or_fail(input);
  for (const char* ext : {"obj", "ply", "off", "stl"}) {
    const std::string out = dir.file(std::string("t.") + ext);
    ASSERT_EQ(pmdec({dir.file("t.pm"), "-o", out, "-q"}).exit_code, 0) << ext;
    const Mesh back = read_or_fail(out);
    EXPECT_TRUE(test::same_faces(original, back)) << ext;
  }
}

// --layer-window SHARE orders the splits as pm::encode with that share does (0: the
// simplifier's order), --layered as whole chunks do; the two exclude each other.
TEST(Cli, LayerWindowSetsTheSplitOrder) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("terrain_holes.obj");
  const Mesh mesh = read_or_fail(input);
  const auto u_order = [](const ProgressiveMesh& pm) {
    std::vector<uint32_t> u;
    for (const VertexSplit& split : pm.splits) u.push_back(split.u);
    return u;
  };
  std::vector<std::vector<uint32_t>> orders;
  for (const double share : {0.0, 1.0 / 16, 0.25, double{INFINITY}}) {
    EncodeOptions options;
    options.layer_window = share;
    ProgressiveMesh expected, written;
    ASSERT_TRUE(encode(mesh, options, expected).is_ok());
    std::vector<std::string> args = {input, "-o", dir.file("t.pm"), "-q"};
    if (share == INFINITY) {
      args.push_back("--layered");
    } else if (share != 1.0 / 16) {  // the default
      args.insert(args.end(), {"--layer-window", std::to_string(share)});
    }
    ASSERT_EQ(pmenc(args).exit_code, 0) << share;
    ASSERT_TRUE(read_pm(test::read_file(dir.file("t.pm")), written).is_ok());
    EXPECT_EQ(u_order(written), u_order(expected)) << share;
    orders.push_back(u_order(written));
  }
  for (std::size_t a = 0; a < orders.size(); ++a)
    for (std::size_t b = a + 1; b < orders.size(); ++b) EXPECT_NE(orders[a], orders[b]) << a << b;
  EXPECT_EQ(pmenc({input, "-o", dir.file("x.pm"), "--layered", "--layer-window", "0.1"}).exit_code,
            2);
  EXPECT_EQ(pmenc({input, "-o", dir.file("x.pm"), "--layer-window", "-1"}).exit_code, 2);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"t.pm"});
  // The library refuses a share that is no number or below zero, and chunks of no split.
  ProgressiveMesh pm;
  EncodeOptions options;
  for (const double share : {-0.5, double{NAN}}) {
    options.layer_window = share;
    EXPECT_EQ(encode(mesh, options, pm).code(), ErrorCode::kInvalidArgument) << share;
  }
  options.layer_window = 0.1;
  WriteOptions no_chunks;
  no_chunks.chunk_splits = 0;
  EXPECT_EQ(encode(mesh, options, no_chunks, pm).code(), ErrorCode::kInvalidArgument);
}

TEST(Cli, ErrorBitsRoundTheErrorsUpByDefaultOnlyWhenQuantized) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("terrain_holes.obj");
  const auto errors = [&](std::vector<std::string> options) {
    std::vector<std::string> args = {input, "-o", dir.file("t.pm"), "-q"};
    args.insert(args.end(), options.begin(), options.end());
    EXPECT_EQ(pmenc(args).exit_code, 0);
    ProgressiveMesh pm;
    EXPECT_TRUE(read_pm(test::read_file(dir.file("t.pm")), pm).is_ok());
    std::vector<float> out;
    for (const VertexSplit& split : pm.splits) out.push_back(split.error);
    return out;
  };
  const std::vector<float> exact = errors({});
  ASSERT_GT(exact.size(), 100u);
  EXPECT_EQ(errors({"--quantize", "14", "--error-bits", "0"}), exact);
  for (const auto& [options, bits] :
       {std::pair<std::vector<std::string>, int>{{"--quantize", "14"}, 5},
        {{"--error-bits", "3"}, 3},
        {{"--quantize", "12", "--error-bits", "8"}, 8}}) {
    const std::vector<float> rounded = errors(options);
    ASSERT_EQ(rounded.size(), exact.size());
    int most_bits = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      ASSERT_GE(rounded[i], exact[i]) << i;
      ASSERT_LE(rounded[i], exact[i] * (1.0f + std::ldexp(1.0f, 1 - bits))) << i;
      if (rounded[i] > 0) most_bits = std::max(most_bits, test::significant_bits(rounded[i]));
    }
    EXPECT_EQ(most_bits, bits) << options.front();
  }
  int most_exact_bits = 0;
  for (float e : exact) if (e > 0) most_exact_bits = std::max(most_exact_bits, test::significant_bits(e));
  EXPECT_GT(most_exact_bits, 8);
  EXPECT_EQ(pmenc({input, "-o", dir.file("x.pm"), "--error-bits", "25"}).exit_code, 2);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"t.pm"});
}

TEST(Cli, DashWritesObjToStandardOutput) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code,
            0);
  const CommandResult r = pmdec({dir.file("s.pm"), "--faces", "100", "-o", "-", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Mesh mesh;
  ASSERT_TRUE(read_mesh_from_memory(r.out, MeshFormat::kObj, mesh).is_ok());
  EXPECT_TRUE(mesh.face_count() == 100 || mesh.face_count() == 101);
}

TEST(Cli, ErrorBoundSelectsALevel) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code,
            0);
  const CommandResult coarse = pmdec({dir.file("s.pm"), "--error", "5%", "-o", dir.file("c.obj")});
  ASSERT_EQ(coarse.exit_code, 0) << coarse.err;
  const CommandResult fine = pmdec({dir.file("s.pm"), "--error", "0.01%", "-o", dir.file("f.obj")});
  ASSERT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_LT(read_or_fail(dir.file("c.obj")).face_count(),
            read_or_fail(dir.file("f.obj")).face_count());
  EXPECT_EQ(pmdec({dir.file("s.pm"), "--error", "abc", "-o", dir.file("e.obj")}).exit_code, 2);
  EXPECT_FALSE(test::file_exists(dir.file("e.obj")));
}

TEST(Cli, InfoPrintsHeaderCountsAndErrorRange) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code,
            0);
  const CommandResult r = pmdec({dir.file("s.pm"), "--info"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* field :
       {"format version:", "base mesh:", "vertex splits:", "full detail:", "error range:"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " missing from\n" << r.out;
}

TEST(Cli, InfoListsTheAttributes) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("textured.obj"), "-o", dir.file("t.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  EXPECT_NE(pmdec({dir.file("t.pm"), "--info"}).out.find(
                "attributes:       colours (rgb); 2011 texture coordinates per corner; 1602 "
                "normals per corner; 2 materials per face; 1 material library\n"),
            std::string::npos);
  EXPECT_NE(pmdec({dir.file("s.pm"), "--info"}).out.find("attributes:       none\n"),
            std::string::npos);
}

// Lossless positions as the text had them (format 2.3): --info says how they are stored, and
// full detail gives every float back, whether the file wrote fixed places ("%f"), a few
// significant digits ("%g"), or floats with every digit.
TEST(Cli, InfoSaysHowLosslessPositionsAreStoredAndFullDetailGivesThemBack) {
  TempDir dir;
  // A tetrahedron in "%g" digits, down to 1.23456e-12: no decimal grid of 15 places holds it.
  test::write_file(dir.file("g.obj"),
                   "v 0.0832331 -52.9283 1.5e-05\nv 1.23456e-12 0.348799 -0.334989\n"
                   "v 0.881192 0.266758 0.181628\nv -0.0399051 0.122726 17.3014\n"
                   "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
  struct Case {
    std::string input;
    const char* positions;
  };
  const Case cases[] = {
      {test::sample_mesh_path("block_features.obj"), "quantization:     positions lossless (decimals, a "},
      {dir.file("g.obj"), "quantization:     positions lossless (decimals of a few significant digits),"},
      {test::sample_mesh_path("sphere.obj"), "quantization:     positions lossless,"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.input);
    const CommandResult encoded = pmenc({c.input, "-o", dir.file("p.pm"), "-q"});
    ASSERT_EQ(encoded.exit_code, 0) << encoded.err;
    const CommandResult info = pmdec({dir.file("p.pm"), "--info"});
    EXPECT_NE(info.out.find(c.positions), std::string::npos) << info.out;
    const CommandResult decoded = pmdec({dir.file("p.pm"), "-o", dir.file("p.obj")});
    ASSERT_EQ(decoded.exit_code, 0) << decoded.err;
    std::vector<float> in = read_or_fail(c.input).positions, out = read_or_fail(dir.file("p.obj")).positions;
    std::vector<uint32_t> in_bits(in.size()), out_bits(out.size());
    std::memcpy(in_bits.data(), in.data(), in.size() * sizeof(float));
    std::memcpy(out_bits.data(), out.data(), out.size() * sizeof(float));
    std::sort(in_bits.begin(), in_bits.end());
    std::sort(out_bits.begin(), out_bits.end());
    EXPECT_EQ(out_bits, in_bits);
  }
}

// --info --sizes: the sections' bytes add up to the file, and the chunk streams are listed in
// bits per split, the texture coordinates' ids among them when the mesh has them.
TEST(Cli, InfoSizesSayWhereTheBytesGo) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("textured.obj"), "-o", dir.file("t.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  for (const char* name : {"t.pm", "s.pm"}) {
    SCOPED_TRACE(name);
    const CommandResult r = pmdec({dir.file(name), "--info", "--sizes"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::size_t at = r.out.find("sections:         header 96 B");
    ASSERT_NE(at, std::string::npos) << r.out;
    // "TAG n B" items add up to the file's size.
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    uint64_t total = 0;
    for (std::size_t p = line.find(' ', 10); p != std::string::npos; p = line.find(" B", p + 1)) {
      std::size_t start = p;
      while (start > 0 && std::isdigit(static_cast<unsigned char>(line[start - 1]))) --start;
      if (start < p) total += std::stoull(line.substr(start, p - start));
    }
    EXPECT_EQ(total, test::read_file(dir.file(name)).size()) << line;
    const bool textured = std::string(name) == "t.pm";
    EXPECT_NE(r.out.find("chunk streams:    bits per split"), std::string::npos);
    EXPECT_EQ(r.out.find("texture coordinate ids ") != std::string::npos, textured) << r.out;
    EXPECT_NE(r.out.find("positions "), std::string::npos);
  }
  EXPECT_EQ(pmdec({dir.file("s.pm"), "--sizes"}).exit_code, 2);  // needs --info
}

// A level lists its faces as the splits made them, materials interleaved; pmdec writes one
// usemtl group per material (the sample has two), the same faces, and with --keep-order the
// input's own order at full detail.
std::size_t count_lines_starting(const std::string& text, const std::string& prefix) {
  std::size_t count = 0;
  for (std::size_t at = 0; at < text.size();) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    count += text.compare(at, prefix.size(), prefix) == 0;
    at = end + 1;
  }
  return count;
}

TEST(Cli, LevelsHaveOneMaterialGroupPerMaterial) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("textured.obj");
  ASSERT_EQ(count_lines_starting(test::read_file(input), "usemtl "), 2u);
  ASSERT_EQ(pmenc({input, "-o", dir.file("t.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmenc({input, "--keep-order", "-o", dir.file("k.pm"), "-q"}).exit_code, 0);
  ProgressiveMesh progressive;
  ASSERT_TRUE(read_pm(test::read_file(dir.file("t.pm")), progressive).ok());
  for (const char* ratio : {"0.02", "0.1", "0.5", "1"}) {
    SCOPED_TRACE(ratio);
    ASSERT_EQ(pmdec({dir.file("t.pm"), "--ratio", ratio, "-o", dir.file("l.obj"), "-q"}).exit_code,
              0);
    const std::string text = test::read_file(dir.file("l.obj"));
    EXPECT_EQ(count_lines_starting(text, "usemtl "), 2u);
    const Mesh level = read_or_fail(dir.file("l.obj"));
    EXPECT_TRUE(test::same_attributed_faces(
        level, extract_level(progressive, level_for_faces(progressive, level.face_count()))));
  }
  // Without grouping the interleaving is real: the library's level has many more switches.
  const Mesh half = extract_level(progressive, progressive.splits.size() / 2);
  std::size_t switches = 0;
  for (std::size_t f = 1; f < half.face_count(); ++f)
    switches += half.face_materials[f] != half.face_materials[f - 1];
  EXPECT_GT(switches, 10u);
  ASSERT_EQ(pmdec({dir.file("k.pm"), "-o", dir.file("k.obj"), "-q"}).exit_code, 0);
  const Mesh original = read_or_fail(input), kept = read_or_fail(dir.file("k.obj"));
  EXPECT_EQ(kept.triangles, original.triangles);
  EXPECT_EQ(kept.face_materials, original.face_materials);
  // A selective mesh with every split applied is not the input's order: grouped.
  ASSERT_EQ(
      pmdec({dir.file("k.pm"), "--region", "sphere:0,0,0,1000", "-o", dir.file("r.obj"), "-q"})
          .exit_code,
      0);
  EXPECT_EQ(read_or_fail(dir.file("r.obj")).face_count(), original.face_count());
  EXPECT_EQ(count_lines_starting(test::read_file(dir.file("r.obj")), "usemtl "), 2u);
}

TEST(Cli, MorphEndsAreTheTwoLevelsAndFramesRunBetweenThem) {
  TempDir dir;
  const std::string pm = dir.file("t.pm");
  ASSERT_EQ(pmenc({test::sample_mesh_path("textured.obj"), "-o", pm, "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({pm, "--lods", "10%,50%", "-o", dir.file("lod_{lod}.obj"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({pm, "--morph", "10%:50%:0", "-o", dir.file("m0.obj"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({pm, "--morph", "10%:50%:1", "-o", dir.file("m1.obj"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({pm, "--morph", "50%:10%:1", "-o", dir.file("back.obj"), "-q"}).exit_code, 0);
  const Mesh coarse = read_or_fail(dir.file("lod_10.obj")), fine = read_or_fail(dir.file("lod_50.obj"));
  EXPECT_TRUE(test::same_attributed_faces(fine, read_or_fail(dir.file("m1.obj"))));
  EXPECT_TRUE(test::same_attributed_faces(coarse, test::without_flat_faces(read_or_fail(dir.file("m0.obj")))));
  // FROM finer than TO runs the morph backwards: alpha 1 is the coarse level.
  EXPECT_EQ(test::read_file(dir.file("back.obj")), test::read_file(dir.file("m0.obj")));
  // Frames: alpha 0, 1/3, 2/3, 1, numbered from 0; the ends are the two levels.
  const CommandResult frames =
      pmdec({pm, "--morph", "10%:50%", "--morph-frames", "4", "-o", dir.file("f_{frame}.obj"), "-q"});
  ASSERT_EQ(frames.exit_code, 0) << frames.err;
  EXPECT_EQ(test::read_file(dir.file("f_0.obj")), test::read_file(dir.file("m0.obj")));
  EXPECT_EQ(test::read_file(dir.file("f_3.obj")), test::read_file(dir.file("m1.obj")));
  const Mesh middle = read_or_fail(dir.file("f_1.obj"));
  EXPECT_EQ(middle.triangles, read_or_fail(dir.file("m1.obj")).triangles);  // the fine connectivity
  // Usage errors: no alpha and no frames, an alpha outside [0, 1], frames without {frame}.
  EXPECT_EQ(pmdec({pm, "--morph", "10%:50%", "-o", dir.file("x.obj")}).exit_code, 2);
  EXPECT_EQ(pmdec({pm, "--morph", "10%:50%:1.5", "-o", dir.file("x.obj")}).exit_code, 2);
  EXPECT_EQ(pmdec({pm, "--morph", "10%:50%", "--morph-frames", "3", "-o", dir.file("x.obj")}).exit_code, 2);
  EXPECT_EQ(pmdec({pm, "--morph", "10%:50%:0.5", "--lods", "10%", "-o", dir.file("x.obj")}).exit_code, 2);
  EXPECT_FALSE(test::file_exists(dir.file("x.obj")));
}

TEST(Cli, HelpAndVersion) {
  for (auto* tool : {PMENC_PATH, PMDEC_PATH}) {
    const CommandResult help = run_command({tool, "--help"});
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_NE(help.out.find("Exit codes"), std::string::npos);
    const CommandResult version = run_command({tool, "--version"});
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_NE(version.out.find("0."), std::string::npos) << version.out;
    EXPECT_EQ(run_command({tool, "--no-such-option"}).exit_code, 2);
  }
}

TEST(Cli, DefaultOutputNameIsTheInputsWithPm) {
  TempDir dir;
  test::write_file(dir.file("m.obj"), test::read_file(test::sample_mesh_path("sphere.obj")));
  ASSERT_EQ(pmenc({dir.file("m.obj"), "-q"}).exit_code, 0);
  EXPECT_TRUE(test::file_exists(dir.file("m.pm")));
}

// Bad input: a clear one-line error naming the file, a documented exit code, no output.
struct BadInput {
  std::string name, content;
  int exit_code;
};

TEST(BadInput, MeshFilesGiveOneLineErrorsAndNoOutput) {
  const std::vector<BadInput> cases = {
      {"empty.obj", "", 4},
      {"blob.obj",
       std::string("\x7f"
                   "ELF\x02\x01\x01\0\0\0\xff\xfe\x00\x13\x88",
                   15) +
           std::string(300, '\xee'),
       4},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4},
      {"text.off", "this is not an off file\n", 4},
      {"mesh.xyz", "v 0 0 0\n", 6},
  };
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.name);
    TempDir dir;
    test::write_file(dir.file(c.name), c.content);
    const CommandResult r = pmenc({dir.file(c.name), "-o", dir.file("out.pm")});
    EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
    expect_one_line_error(r, "pmenc", dir.file(c.name));
    EXPECT_EQ(listing(dir.path()), std::vector<std::string>{c.name});
  }
}

TEST(BadInput, MissingInputAndUnwritableOutput) {
  TempDir dir;
  CommandResult r = pmenc({dir.file("nope.obj"), "-o", dir.file("out.pm")});
  EXPECT_EQ(r.exit_code, 3);
  expect_one_line_error(r, "pmenc", dir.file("nope.obj"));
  r = pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("no/such/dir/out.pm")});
  EXPECT_EQ(r.exit_code, 5);
  expect_one_line_error(r, "pmenc", dir.file("no/such/dir/out.pm"));
  r = pmdec({dir.file("nope.pm"), "-o", dir.file("out.obj")});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(listing(dir.path()).empty());
}

// pmdec gives a mesh to its file as the writer makes it (cli_common.h, write_mesh_output()):
// an output that fails at its first byte (no such directory) or in the middle of the text
// (the file size limit: `ulimit -f` counts 512-byte blocks, and with SIGXFSZ ignored write()
// fails with EFBIG) leaves no file and no temporary, and exits with "cannot write".
TEST(BadInput, PmdecOutputThatFailsLeavesNothing) {
  TempDir dir;
  std::string obj;  // 3,200 faces: about 150 KB of OBJ at full detail, 290 KB of PLY
  ASSERT_TRUE(write_mesh_to_memory(test::seamed_grid(40), MeshFormat::kObj, obj).is_ok());
  test::write_file(dir.file("grid.obj"), obj);
  ASSERT_EQ(pmenc({dir.file("grid.obj"), "-o", dir.file("grid.pm"), "-q"}).exit_code, 0);
  CommandResult r = pmdec({dir.file("grid.pm"), "-o", dir.file("no/such/dir/full.obj")});
  EXPECT_EQ(r.exit_code, 5);
  expect_one_line_error(r, "pmdec", dir.file("no/such/dir/full.obj"));
  for (const char* name : {"full.obj", "full.ply"}) {
    SCOPED_TRACE(name);
    r = run_command({"/bin/sh", "-c", "trap '' XFSZ; ulimit -f 64; exec \"$0\" \"$@\"", PMDEC_PATH,
                     dir.file("grid.pm"), "-o", dir.file(name)});
    EXPECT_EQ(r.exit_code, 5);
    expect_one_line_error(r, "pmdec", dir.file(name));
    EXPECT_NE(r.err.find("cannot write output: File too large"), std::string::npos) << r.err;
  }
  EXPECT_EQ(listing(dir.path()), (std::vector<std::string>{"grid.obj", "grid.pm"}));
}

TEST(BadInput, TruncatedPmAtManyOffsetsFailsCleanly) {
  TempDir dir;
  ASSERT_EQ(
      pmenc({test::sample_mesh_path("terrain_holes.obj"), "-o", dir.file("t.pm"), "-q"}).exit_code,
      0);
  const std::string whole = test::read_file(dir.file("t.pm"));
  ASSERT_GT(whole.size(), 100u);
  // Every byte of the header region, then offsets spread over the rest (the codec's own
  // tests cut in-process at every single byte).
  std::vector<std::size_t> cuts;
  for (std::size_t i = 0; i < 96; ++i) cuts.push_back(i);
  for (std::size_t i = 96; i < whole.size(); i += std::max<std::size_t>(1, whole.size() / 60))
    cuts.push_back(i);
  cuts.push_back(whole.size() - 1);
  // A cut in the header or the base part (format 2.0: up to the chunk index) is an error;
  // a later cut gives the finest level the stream holds, a warning and exit code 9.
  bool decoding = false;
  std::size_t decoded = 0;
  for (std::size_t cut : cuts) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    test::write_file(dir.file("cut.pm"), whole.substr(0, cut));
    std::remove(dir.file("out.obj").c_str());
    const CommandResult r = pmdec({dir.file("cut.pm"), "-o", dir.file("out.obj")});
    if (r.exit_code == 9) {
      decoding = true;
      ++decoded;
      EXPECT_NE(r.err.find("pmdec: " + dir.file("cut.pm") + ": warning: truncated in"), std::string::npos) << r.err;
      EXPECT_TRUE(test::file_exists(dir.file("out.obj")));
      continue;
    }
    EXPECT_FALSE(decoding) << "an error after a longer prefix decoded";
    EXPECT_EQ(r.exit_code, 4) << r.err;
    expect_one_line_error(r, "pmdec", dir.file("cut.pm"));
    EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  }
  EXPECT_GT(decoded, 10u);
}

TEST(BadInput, UsageErrors) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code,
            0);
  EXPECT_EQ(pmdec({dir.file("s.pm"), "--faces", "10", "--ratio", "0.5", "-o", dir.file("a.obj")})
                .exit_code,
            2);
  EXPECT_EQ(pmdec({dir.file("s.pm"), "--ratio", "1.5", "-o", dir.file("a.obj")}).exit_code, 2);
  EXPECT_EQ(pmdec({dir.file("s.pm"), "-o", dir.file("a.xyz")}).exit_code, 6);
  EXPECT_EQ(pmdec({dir.file("s.pm")}).exit_code, 2);
  EXPECT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "--feature-angle", "-3"}).exit_code, 2);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"s.pm"});
}

TEST(Cli, ReportsRepairsOnStderr) {
  TempDir dir;
  const CommandResult r =
      pmenc({test::sample_mesh_path("nonmanifold.obj"), "-o", dir.file("n.pm")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("repaired"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-manifold edges cut"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("faces with a repeated vertex"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pm

namespace pm {
namespace {

TEST(Cli, MetricOptionSelectsTheCost) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("block_features.obj");
  ASSERT_EQ(pmenc({input, "--metric", "quadric", "-o", dir.file("q.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmenc({input, "--metric", "schroeder", "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  // Different costs give different sequences, and each decodes to the input.
  EXPECT_NE(test::read_file(dir.file("q.pm")), test::read_file(dir.file("s.pm")));
  ASSERT_EQ(pmdec({dir.file("q.pm"), "-o", dir.file("q.obj"), "-q"}).exit_code, 0);
  EXPECT_TRUE(test::same_faces(read_or_fail(input), read_or_fail(dir.file("q.obj"))));
  EXPECT_EQ(pmenc({input, "--metric", "volume", "-o", dir.file("x.pm")}).exit_code, 2);
  EXPECT_FALSE(test::file_exists(dir.file("x.pm")));
}

// --fast leaves out the loop's measured distance: another sequence, with either metric,
// with attributes or without, and "loop":"fast" in --json ("default" without it); full
// detail is still the input exactly, texture coordinates and materials too.
TEST(Cli, FastLeavesOutTheMeasuredDistance) {
  TempDir dir;
  const std::string block = test::sample_mesh_path("block_features.obj");
  const std::string textured = test::sample_mesh_path("textured.obj");
  struct Run {
    std::string input;
    std::vector<std::string> options;
  };
  const Run runs[] = {{block, {}},
                      {block, {"--metric", "schroeder"}},
                      {textured, {}},
                      {textured, {"--drop-attributes"}}};
  int n = 0;
  for (const Run& run : runs) {
    const std::string plain = dir.file("plain" + std::to_string(n) + ".pm");
    const std::string fast = dir.file("fast" + std::to_string(n) + ".pm");
    ++n;
    std::vector<std::string> args = {run.input, "-o", plain, "--json"};
    args.insert(args.end(), run.options.begin(), run.options.end());
    const CommandResult measured = pmenc(args);
    ASSERT_EQ(measured.exit_code, 0) << measured.err;
    EXPECT_NE(measured.out.find("\"loop\":\"default\""), std::string::npos) << measured.out;
    args = {run.input, "--fast", "-o", fast, "--json"};
    args.insert(args.end(), run.options.begin(), run.options.end());
    const CommandResult with_fast = pmenc(args);
    ASSERT_EQ(with_fast.exit_code, 0) << with_fast.err;
    EXPECT_NE(with_fast.out.find("\"loop\":\"fast\""), std::string::npos) << with_fast.out;
    EXPECT_EQ(with_fast.err.find("--fast"), std::string::npos) << with_fast.err;  // asked for
    EXPECT_NE(test::read_file(fast), test::read_file(plain)) << run.input;
    ASSERT_EQ(pmdec({fast, "-o", dir.file("full.obj"), "-q"}).exit_code, 0);
    const Mesh in = read_or_fail(run.input), out = read_or_fail(dir.file("full.obj"));
    EXPECT_TRUE(test::same_faces(in, out)) << run.input;
  }
  // Texture coordinates and materials come back at full detail.
  ASSERT_EQ(pmdec({dir.file("fast2.pm"), "-o", dir.file("t.obj"), "-q"}).exit_code, 0);
  const Mesh textured_in = read_or_fail(textured), textured_out = read_or_fail(dir.file("t.obj"));
  EXPECT_EQ(textured_out.uvs.size(), textured_in.uvs.size());
  EXPECT_EQ(textured_out.face_materials.size(), textured_in.face_materials.size());
}

}  // namespace
}  // namespace pm

namespace pm {
namespace {

// ---------------------------------------------------------------------------------------
// Hardening (issue 9): pmdec --max-memory, the invalid models of assimp-testmodels.

TEST(Cli, MaxMemoryRefusesLargerDecodesWithExitCode7) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code,
            0);
  ASSERT_EQ(pmdec({dir.file("s.pm"), "-o", dir.file("free.obj"), "-q"}).exit_code, 0);
  const std::size_t file_size = test::read_file(dir.file("s.pm")).size();
  // The file itself counts: one byte less than it is refused before decoding, whatever the
  // suffix (k is 1024 bytes).
  const std::size_t below_in_k = (file_size - 1) / 1024;
  const std::vector<std::pair<std::string, std::size_t>> limits = {
      {std::to_string(file_size - 1), file_size - 1},
      {std::to_string(below_in_k) + "k", below_in_k * 1024},
      {std::to_string(below_in_k) + "KiB", below_in_k * 1024}};
  for (const auto& [limit, bytes] : limits) {
    SCOPED_TRACE(limit);
    const CommandResult r =
        pmdec({dir.file("s.pm"), "--max-memory", limit, "-o", dir.file("out.obj")});
    EXPECT_EQ(r.exit_code, 7) << r.err;
    EXPECT_EQ(r.err, "pmdec: " + dir.file("s.pm") + ": input is " + std::to_string(file_size) +
                         " bytes, more than the memory limit of " + std::to_string(bytes) +
                         " bytes\n");
  }
  // A limit the file fits in but its decoded mesh (positions, faces, splits) does not:
  // refused by the decoder, before it allocates, in one line.
  CommandResult r = pmdec(
      {dir.file("s.pm"), "--max-memory", std::to_string(file_size), "-o", dir.file("out.obj")});
  EXPECT_EQ(r.exit_code, 7) << r.err;
  expect_one_line_error(r, "pmdec", dir.file("s.pm"));
  EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  // Generous limits in every spelling decode the same bytes as no limit.
  for (const char* limit : {"1000000", "1M", "512M", "2G", "2g", "1T", "4MB", "1.5M"}) {
    SCOPED_TRACE(limit);
    r = pmdec({dir.file("s.pm"), "--max-memory", limit, "-o", dir.file("out.obj"), "-q"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(test::read_file(dir.file("out.obj")), test::read_file(dir.file("free.obj")));
  }
  for (const char* bad : {"", "abc", "0", "-5", "12Q", "1.2.3", "M", "5 M"}) {
    SCOPED_TRACE(bad);
    r = pmdec({dir.file("s.pm"), "--max-memory", bad, "-o", dir.file("bad.obj")});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_FALSE(test::file_exists(dir.file("bad.obj")));
  }
  // Standard input is bounded while it is read.
  r = test::run_command({PMDEC_PATH, "-", "--max-memory", std::to_string(file_size - 1), "-o", "-"},
                        test::read_file(dir.file("s.pm")));
  EXPECT_EQ(r.exit_code, 7) << r.err;
  EXPECT_EQ(r.out, "");
}

// Every file of Debian's assimp-testmodels "invalid" folder: a one-line error naming the
// file with a documented exit code, or, for a mesh that is valid after all, a conversion
// (with its repairs reported) and exit 0. Never a signal, never a partial or stray file.
TEST(BadInput, AssimpInvalidModelsFailCleanly) {
  const std::string folder = "/usr/share/assimp/models/invalid";
  if (!test::file_exists(folder)) {
    std::cerr << folder << " not found (Debian package assimp-testmodels): skipping\n";
    GTEST_SKIP() << folder << " not found";
  }
  std::vector<std::string> names = listing(folder);
  ASSERT_FALSE(names.empty());
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    TempDir dir;
    const std::string input = folder + "/" + name;
    const CommandResult r = pmenc({input, "-o", dir.file("out.pm")});
    EXPECT_LT(r.exit_code, 128) << "killed by signal " << r.exit_code - 128;
    if (r.exit_code == 0) {
      EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"out.pm"});
      ProgressiveMesh progressive;
      EXPECT_TRUE(read_pm(test::read_file(dir.file("out.pm")), progressive).is_ok());
      continue;
    }
    EXPECT_TRUE(r.exit_code == 3 || r.exit_code == 4 || r.exit_code == 6 || r.exit_code == 7)
        << r.exit_code << ": " << r.err;
    expect_one_line_error(r, "pmenc", input);
    EXPECT_GT(r.err.size(), ("pmenc: " + input + ": \n").size()) << "no message";
    EXPECT_TRUE(listing(dir.path()).empty());
  }
}

// --drop-attributes: the geometry, exactly, and nothing else.
TEST(Cli, DropAttributesKeepsTheFacesOnly) {
  TempDir dir;
  // polygons.obj has texture coordinates, normals and a material.
  const std::string input = test::sample_mesh_path("polygons.obj");
  ASSERT_EQ(pmenc({input, "--drop-attributes", "-o", dir.file("p.pm"), "-q"}).exit_code, 0);
  ProgressiveMesh progressive;
  ASSERT_TRUE(read_pm(test::read_file(dir.file("p.pm")), progressive).is_ok());
  EXPECT_FALSE(progressive.has_uvs());
  EXPECT_FALSE(progressive.has_normals());
  EXPECT_FALSE(progressive.has_materials());
  EXPECT_TRUE(progressive.colors.empty());
  EXPECT_TRUE(
      test::same_faces(read_or_fail(input), extract_level(progressive, progressive.splits.size())));
}

// ---------------------------------------------------------------------------------------
// Man pages: written by hand, installed by cmake --install; they must describe every
// option --help lists and every exit code.

std::string man_page(const std::string& tool) {
  return test::read_file(std::string(PM_SAMPLES_DIR) + "/../apps/man/" + tool + ".1");
}

// The long options of --help, e.g. "--out-dir".
std::vector<std::string> long_options(const std::string& help) {
  std::vector<std::string> options;
  for (std::size_t at = help.find("--"); at != std::string::npos; at = help.find("--", at + 2)) {
    std::size_t end = at + 2;
    while (end < help.size() &&
           (std::islower(static_cast<unsigned char>(help[end])) || help[end] == '-'))
      ++end;
    if (end > at + 2) options.push_back(help.substr(at, end - at));
  }
  std::sort(options.begin(), options.end());
  options.erase(std::unique(options.begin(), options.end()), options.end());
  return options;
}

TEST(Cli, ManPagesDescribeEveryOptionAndExitCode) {
  for (const char* tool : {"pmenc", "pmdec"}) {
    SCOPED_TRACE(tool);
    const std::string page = man_page(tool);
    const CommandResult help =
        run_command({std::string(tool) == "pmenc" ? PMENC_PATH : PMDEC_PATH, "--help"});
    ASSERT_EQ(help.exit_code, 0);
    const std::vector<std::string> options = long_options(help.out);
    EXPECT_GE(options.size(), 15u);
    for (const std::string& option : options) {
      std::string roff;  // "--out-dir" is written "\-\-out\-dir"
      for (char c : option) roff += c == '-' ? std::string("\\-") : std::string(1, c);
      EXPECT_NE(page.find("\\fB" + roff + "\\fR"), std::string::npos) << option;
    }
    for (int code = 0; code <= 8; ++code)
      EXPECT_NE(page.find(".TP\n.B " + std::to_string(code) + "\n"), std::string::npos) << code;
    // groff, when there, renders the page without a warning.
    if (test::file_exists("/usr/bin/groff")) {
      const CommandResult render =
          run_command({"/usr/bin/groff", "-man", "-Tutf8", "-wall",
                       std::string(PM_SAMPLES_DIR) + "/../apps/man/" + tool + ".1"});
      EXPECT_EQ(render.exit_code, 0);
      EXPECT_EQ(render.err, "");
    }
  }
}

// Meshes of at least --fast-from faces take --fast without being asked, and say so: the
// stream is then --fast's, byte for byte, with or without attributes. Below it, or with 0,
// the measured distance stays, silently. It is checked: a whole number.
TEST(Cli, LargeMeshesTakeFastFromAFaceCount) {
  TempDir dir;
  const std::string block = test::sample_mesh_path("block_features.obj");
  const std::size_t faces = read_or_fail(block).face_count();
  ASSERT_GT(faces, 2u);
  ASSERT_EQ(pmenc({block, "-o", dir.file("default.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmenc({block, "--fast", "-o", dir.file("fast.pm"), "-q"}).exit_code, 0);
  ASSERT_NE(test::read_file(dir.file("fast.pm")), test::read_file(dir.file("default.pm")));
  for (const std::string& from : {std::to_string(faces), std::string("1")}) {
    const CommandResult large = pmenc({block, "--fast-from", from, "-o", dir.file("at.pm"), "--json"});
    ASSERT_EQ(large.exit_code, 0) << large.err;
    EXPECT_NE(large.out.find("\"loop\":\"fast\""), std::string::npos) << from << large.out;
    EXPECT_NE(large.err.find(block + ": " + std::to_string(faces) + " faces, at least --fast-from " +
                             from + ": --fast"),
              std::string::npos)
        << large.err;
    EXPECT_EQ(test::read_file(dir.file("at.pm")), test::read_file(dir.file("fast.pm"))) << from;
  }
  for (const std::string& from : {std::to_string(faces + 1), std::string("0")}) {
    const CommandResult small = pmenc({block, "--fast-from", from, "-o", dir.file("s.pm"), "--json"});
    ASSERT_EQ(small.exit_code, 0) << small.err;
    EXPECT_NE(small.out.find("\"loop\":\"default\""), std::string::npos) << from << small.out;
    EXPECT_EQ(small.err.find("fast"), std::string::npos) << from << small.err;
    EXPECT_EQ(test::read_file(dir.file("s.pm")), test::read_file(dir.file("default.pm"))) << from;
  }
  // With attributes: --fast's stream too, and full detail restores the texture coordinates.
  const std::string textured = test::sample_mesh_path("textured.obj");
  ASSERT_EQ(pmenc({textured, "--fast", "-o", dir.file("t_fast.pm"), "-q"}).exit_code, 0);
  const CommandResult kept = pmenc({textured, "--fast-from", "1", "-o", dir.file("t.pm"), "--json"});
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_NE(kept.out.find("\"loop\":\"fast\""), std::string::npos) << kept.out;
  EXPECT_EQ(test::read_file(dir.file("t.pm")), test::read_file(dir.file("t_fast.pm")));
  ASSERT_EQ(pmdec({dir.file("t.pm"), "-o", dir.file("t.obj"), "-q"}).exit_code, 0);
  EXPECT_EQ(read_or_fail(dir.file("t.obj")).uvs.size(), read_or_fail(textured).uvs.size());
  ASSERT_EQ(pmenc({block, "--fast-from", "1", "-o", dir.file("at.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({dir.file("at.pm"), "-o", dir.file("at.obj"), "-q"}).exit_code, 0);
  EXPECT_TRUE(test::same_faces(read_or_fail(block), read_or_fail(dir.file("at.obj"))));
  // A negative count is a usage error, not 2^64 - 3 (no limit), in every count option.
  for (const char* option : {"--fast-from", "--min-faces", "--min-vertices"}) {
    const CommandResult negative = pmenc({block, option, "-3", "-o", dir.file("x.pm")});
    EXPECT_EQ(negative.exit_code, 2) << option;
    EXPECT_NE(negative.err.find(std::string(option) + ": must be a whole number"), std::string::npos)
        << negative.err;
    EXPECT_FALSE(test::file_exists(dir.file("x.pm")));
  }
  for (const char* option : {"--faces", "--vertices"}) {
    EXPECT_EQ(pmdec({dir.file("at.pm"), option, "-3", "-o", dir.file("x.obj")}).exit_code, 2) << option;
    EXPECT_FALSE(test::file_exists(dir.file("x.obj")));
  }
}

}  // namespace
}  // namespace pm
