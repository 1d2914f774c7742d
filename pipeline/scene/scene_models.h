#pragma once
// [[models]] entries of a scene (docs/scenes.md): a 3-D model file read through Assimp
// (model_loader.h), placed like a [[meshes]] entry; its faces take one texsim material, or
// each the material made from the file's own (its diffuse texture with the entry's `effects`,
// default filter settings without them).
#include <toml++/toml.h>

#include "pipeline/scene/scene.h"

namespace texsim {

// Appends every model's faces to s.primitives (after the meshes) and the models to s.meshes;
// the file's materials become s.textures and s.materials entries named "MODEL.MATERIAL".
// Throws InputError naming file:line:column of the entry, or the model file.
void parse_models(const toml::table& root, Scene& s);

}  // namespace texsim
