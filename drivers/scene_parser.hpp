#pragma once
// Scene files: YAML -> cgdem::Scene (core/scene.hpp), with --set overrides and validation.
// The format is documented key by key in docs/scene_format.md.
//
// Every problem with a scene is reported as a cgdem::SceneError whose what() is one line:
//   <file>:<line>: <key.path>: <what is wrong>; <the fix>
// For a value that came from a --set override the "<line>" is replaced by the override itself:
//   <file>:--set 'groups.0.count=-1': groups.0.count: ...
#include <stdexcept>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace cgdem {

class SceneError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Builds the one-line message: "<location>: <key_path>: <what>; <fix>" (location is "file:line" or
// "file:--set '...'"; an empty key_path is left out, an empty fix too). Newlines are flattened.
std::string scene_error_message(const std::string& location, const std::string& key_path,
                                const std::string& what, const std::string& fix);

// Reads, overrides, validates. `overrides` are "key.path=value" strings (the command line's --set):
// nested map keys and list indices separated by '.', the value parsed as YAML. Applied in order to the
// YAML tree before validation; the path must exist except for a new last key under an existing map.
// Relative particle file paths (groups.N.placement.file) are resolved against the scene file's directory.
Scene parse_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});

// Same from text; `source_name` names the scene in messages, and its directory (if it has one) anchors
// relative particle file paths (otherwise they stay relative to the working directory).
Scene parse_scene_text(const std::string& yaml, const std::string& source_name,
                       const std::vector<std::string>& overrides = {});

// Levenshtein distance (used for "did you mean" suggestions; exposed for tests).
std::size_t edit_distance(const std::string& a, const std::string& b);

} // namespace cgdem
