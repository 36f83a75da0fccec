// validatedMeshText: the check every mesh file passes before OpenMesh's readers see it. Fuzzing found
// OpenMesh 9's readers crashing (a malformed PLY header), asserting (short OBJ faces) and allocating
// without bound (an OFF face announcing billions of corners), and going on with unset values after a
// number fails to parse. So the structure is checked here, strictly, and OpenMesh gets only text it
// handles: element counts against the file size, every number finite, every face of 3 or more corners
// with indices in range, PLY headers of known keywords and types, no control characters in ASCII.
//   path: the file's name (its extension picks the format) for messages
//   text: the file's bytes
// Returns the text to hand to OpenMesh: for ASCII OFF and OBJ without comments and blank lines, and
// OFF faces without their colours (which OpenMesh cannot parse). Throws isoatlas::Error naming the
// file and line.
#pragma once
#include <string>

namespace isoatlas {

std::string validatedMeshText(const std::string& path, const std::string& text);

}  // namespace isoatlas
