#pragma once
// The bytes in which an isolated reader (isolate.hpp) hands its meshes to the parent: a
// simple format of our own, read back with every count checked against the bytes the child
// announced before anything is allocated. Native byte order: the writer is a fork of the reader.
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>

#include <memory>
#include <string>
#include <vector>

namespace dawnforge::detail {

// The answer that writes `nodes`.
Answer encodeNodes(std::shared_ptr<const std::vector<MeshNode>> nodes);

// Throws InputError ("FILE: the reader's answer is damaged (...)") if the bytes are not what
// encodeNodes writes, or a node's parent does not come before it. The meshes get no other
// check here: the caller validates them as it would any file's.
std::vector<MeshNode> decodeNodes(AnswerSource& source, const std::string& name);

}  // namespace dawnforge::detail
