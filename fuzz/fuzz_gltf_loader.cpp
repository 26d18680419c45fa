// libFuzzer target for the glTF loader: every input is read as .gltf JSON, as a .glb, and wrapped
// as the JSON chunk of a .glb (so JSON mutations also reach the binary path). A SceneError is the
// loader refusing a bad file, which is fine; any other exception escapes and counts as a crash,
// as do sanitizer reports and hangs (scripts/fuzz.sh runs it with -timeout).
#include "scene/gltf_loader.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

void load(const std::string& bytes, bool binary) {
  try {
    bp::load_gltf_from_memory(bytes, "fuzz-input", binary);
  } catch (const bp::SceneError&) {
  }
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += char((v >> (8 * i)) & 0xffu);
}

// A .glb with `json` as its JSON chunk (space-padded to 4 bytes, as the spec asks) and no BIN chunk.
std::string as_glb(std::string json) {
  while (json.size() % 4) json += ' ';
  std::string out = "glTF";
  put_u32(out, 2u);
  put_u32(out, std::uint32_t(12 + 8 + json.size()));
  put_u32(out, std::uint32_t(json.size()));
  put_u32(out, 0x4E4F534Au);  // "JSON"
  return out + json;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  if (size >= 4 && bytes.compare(0, 4, "glTF") == 0) {
    load(bytes, true);
  } else {
    load(bytes, false);
    load(as_glb(bytes), true);
  }
  return 0;
}
