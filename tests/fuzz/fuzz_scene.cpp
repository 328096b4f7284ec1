// libFuzzer target: the scene parser with --set overrides (drivers/scene_parser.hpp).
// Input: a scene's YAML text, then optionally a line "#--set" followed by one override per line.
// Every input must end in a Scene or a SceneError; anything else (crash, other exception) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "drivers/scene_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string marker = "\n#--set\n";
  const auto cut = text.find(marker);
  const std::string yaml = text.substr(0, cut);
  std::vector<std::string> overrides;
  if (cut != std::string::npos) {
    std::string rest = text.substr(cut + marker.size());
    std::size_t start = 0;
    while (start <= rest.size() && overrides.size() < 8) {
      const auto end = rest.find('\n', start);
      overrides.push_back(rest.substr(start, end == std::string::npos ? std::string::npos : end - start));
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }
  try {
    cgdem::parse_scene_text(yaml, "fuzz.yaml", overrides);
  } catch (const cgdem::SceneError&) {
  }
  return 0;
}
