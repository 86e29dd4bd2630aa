// The files a mesh names (an OBJ's material libraries, a glTF's buffers
// and images, ...), as assimp opens them: regular files only.
//
// A named pipe would block the import in open() until its time limit, and
// a device or a folder is no file to read. Each is refused before anything
// opens it, and the import then fails naming the file and what is there
// (base/files.hpp), rather than going on without it.
//
// Takes: the paths assimp asks for. Gives: assimp's own file streams for
// regular files; for anything else, nothing, and refused() says why.
#pragma once

#include "facet/error.hpp"

#include <assimp/DefaultIOSystem.h>

#include <optional>
#include <vector>

namespace facet {

class RegularFilesOnly : public Assimp::DefaultIOSystem {
public:
    bool Exists(const char* file) const override;
    Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;

    // The first file refused, with what is there, that no file of the
    // same name opened later stood in for; nothing if there is none.
    // (assimp looks for a file a mesh names at several places in turn: as
    // written, from the working folder, then beside the mesh.)
    std::optional<Error> refused() const;

private:
    // Whether `file` may be opened; records a refusal. (Exists is const in
    // assimp's interface.)
    bool allowed(const char* file) const;

    mutable std::vector<Error> refused_;
};

}  // namespace facet
