// glTF through the tools (issue 29): pmenc reads .gltf/.glb like any mesh, pmdec writes one
// level or a whole --lods chain into one file, round trips are exact, hostile files are
// refused with one line and no output. The validator and three.js checks are
// tests/gltf/run.sh (CTest Gltf.ValidatorAndThree).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/gltf_glb.h"
#include "pm/gltf.h"
#include "pm/mesh_io.h"
#include "test_util.h"

namespace pm {
namespace {

using test::CommandResult;
using test::TempDir;

CommandResult pmenc(std::vector<std::string> args) {
  args.insert(args.begin(), PMENC_PATH);
  return test::run_command(args);
}
CommandResult pmdec(std::vector<std::string> args) {
  args.insert(args.begin(), PMDEC_PATH);
  return test::run_command(args);
}

Mesh read_or_fail(const std::string& path) {
  Mesh mesh;
  const Status s = read_mesh(path, mesh);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  return mesh;
}

nlohmann::json glb_json(const std::string& path) {
  const std::string bytes = test::read_file(path);
  detail::GlbChunks chunks;
  EXPECT_TRUE(detail::split_glb(bytes, chunks).is_ok()) << path;
  return nlohmann::json::parse(chunks.json);
}

// OBJ -> .pm -> .glb full detail -> .pm -> OBJ: the input's faces, positions and corner
// attributes (texture coordinates across seams, normals, colours, materials), bit for bit.
TEST(GltfCli, ObjThroughGlbAndBackIsExact) {
  TempDir dir;
  const std::string input = test::sample_mesh_path("textured.obj");
  ASSERT_EQ(pmenc({input, "-o", dir.file("a.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({dir.file("a.pm"), "-o", dir.file("full.glb"), "-q"}).exit_code, 0);
  const CommandResult encoded = pmenc({dir.file("full.glb"), "-o", dir.file("b.pm")});
  ASSERT_EQ(encoded.exit_code, 0) << encoded.err;
  ASSERT_EQ(pmdec({dir.file("b.pm"), "-o", dir.file("back.obj"), "-q"}).exit_code, 0);
  EXPECT_TRUE(test::same_attributed_faces(read_or_fail(input), read_or_fail(dir.file("back.obj"))));
}

TEST(GltfCli, LodsWriteOneChainFile) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("textured.obj"), "-o", dir.file("a.pm"), "-q"}).exit_code, 0);
  const CommandResult r =
      pmdec({dir.file("a.pm"), "--lods", "100%,25%,5%", "-o", dir.file("chain.glb"), "--json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // One file, not one per level.
  EXPECT_TRUE(test::file_exists(dir.file("chain.glb")));
  const nlohmann::json report = nlohmann::json::parse(r.out);
  ASSERT_EQ(report["outputs"].size(), 3u);
  const nlohmann::json d = glb_json(dir.file("chain.glb"));
  EXPECT_EQ(d["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json({1, 2}));
  for (int n = 0; n < 3; ++n) {
    std::size_t faces = 0;
    for (const auto& primitive : d["meshes"][n]["primitives"])
      faces += d["accessors"][primitive["indices"].get<int>()]["count"].get<std::size_t>() / 3;
    EXPECT_EQ(faces, report["outputs"][n]["faces"].get<std::size_t>()) << "level " << n;
  }
  // The finest level is what a reader without MSFT_lod gets: the input's faces.
  EXPECT_TRUE(test::same_attributed_faces(read_or_fail(test::sample_mesh_path("textured.obj")),
                                          read_or_fail(dir.file("chain.glb"))));
  // Quantized: required extension.
  ASSERT_EQ(pmdec({dir.file("a.pm"), "--lods", "100%,25%", "--quantize", "-o", dir.file("q.glb"), "-q"}).exit_code, 0);
  EXPECT_EQ(glb_json(dir.file("q.glb"))["extensionsRequired"], nlohmann::json({"KHR_mesh_quantization"}));
  // --quantize is for glTF only.
  EXPECT_EQ(pmdec({dir.file("a.pm"), "--quantize", "-o", dir.file("q.obj"), "-q"}).exit_code, 2);
}

TEST(GltfCli, MaterialFromCopiesDefinitions) {
  TempDir dir;
  // A source glTF: pmdec's own output with a textured definition for "skin".
  ASSERT_EQ(pmenc({test::sample_mesh_path("textured.obj"), "-o", dir.file("a.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({dir.file("a.pm"), "-o", dir.file("plain.gltf"), "-q"}).exit_code, 0);
  nlohmann::json source = nlohmann::json::parse(test::read_file(dir.file("plain.gltf")));
  ASSERT_FALSE(source["materials"].empty());
  const std::string name = source["materials"][0]["name"];
  source["materials"][0]["pbrMetallicRoughness"] = {{"baseColorTexture", {{"index", 0}}}};
  source["textures"] = {{{"source", 0}}};
  source["images"] = {{{"uri", "vase.png"}}};
  test::write_file(dir.file("source.gltf"), source.dump());
  ASSERT_EQ(pmdec({dir.file("a.pm"), "--ratio", "0.5", "--material-from", dir.file("source.gltf"), "-o",
                   dir.file("out.glb"), "-q"})
                .exit_code,
            0);
  const nlohmann::json d = glb_json(dir.file("out.glb"));
  bool found = false;
  for (const auto& material : d["materials"])
    if (material["name"] == name) {
      found = true;
      EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    }
  EXPECT_TRUE(found);
  EXPECT_EQ(d["images"][0]["uri"], "vase.png");  // same directory as the output
}

TEST(GltfCli, PmencFindsGltfWithRecursive) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  std::filesystem::create_directories(dir.file("in"));
  ASSERT_EQ(pmdec({dir.file("s.pm"), "-o", dir.file("in/a.glb"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({dir.file("s.pm"), "-o", dir.file("in/b.gltf"), "-q"}).exit_code, 0);
  const CommandResult r = pmenc({"-r", dir.file("in"), "--out-dir", dir.file("out"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // Both found, whatever folders --out-dir mirrors.
  std::vector<std::string> written;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir.file("out")))
    if (entry.is_regular_file()) written.push_back(entry.path().filename().string());
  std::sort(written.begin(), written.end());
  EXPECT_EQ(written, (std::vector<std::string>{"a.pm", "b.pm"})) << r.err;
}

TEST(GltfCli, HostileGlbIsOneLineAndNoOutput) {
  TempDir dir;
  ASSERT_EQ(pmenc({test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  ASSERT_EQ(pmdec({dir.file("s.pm"), "-o", dir.file("s.glb"), "-q"}).exit_code, 0);
  const std::string glb = test::read_file(dir.file("s.glb"));
  test::write_file(dir.file("cut.glb"), glb.substr(0, glb.size() / 2));
  const CommandResult cut = pmenc({dir.file("cut.glb"), "-o", dir.file("cut.pm")});
  EXPECT_EQ(cut.exit_code, 4) << cut.err;
  EXPECT_EQ(std::count(cut.err.begin(), cut.err.end(), '\n'), 1) << cut.err;
  EXPECT_NE(cut.err.find("cut.glb: "), std::string::npos) << cut.err;
  EXPECT_FALSE(test::file_exists(dir.file("cut.pm")));
  // Draco: refused as unsupported (exit 6), naming the extension.
  nlohmann::json d = glb_json(dir.file("s.glb"));
  d["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  d["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  detail::GlbChunks chunks;
  ASSERT_TRUE(detail::split_glb(glb, chunks).is_ok());
  test::write_file(dir.file("draco.glb"), detail::make_glb(d.dump(), chunks.binary));
  const CommandResult draco = pmenc({dir.file("draco.glb"), "-o", dir.file("draco.pm")});
  EXPECT_EQ(draco.exit_code, 6) << draco.err;
  EXPECT_NE(draco.err.find("KHR_draco_mesh_compression"), std::string::npos) << draco.err;
  EXPECT_FALSE(test::file_exists(dir.file("draco.pm")));
}

}  // namespace
}  // namespace pm
