#pragma once
// What a run report needs to be reproduced: the texsim version, the command, a digest of every
// input file, and the resolved configuration with every default written out. Nothing in it
// changes from one run of the same command to the next, so reports stay byte-reproducible.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/energy_table.h"
#include "blocks/base/tech_table.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

struct InputDigest {
  std::string role;  // "scene", "trace", "texture <name>"
  std::string path;  // as given (procedural textures: their spec, no digest)
  std::string sha1;  // hex SHA-1 of the file's bytes (sha1sum gives the same); "" = not a file
  uint64_t bytes = 0;
};

struct Provenance {
  std::string version;  // texsim version
  std::string command;  // the command line, "texsim" then the arguments as given
  std::vector<InputDigest> inputs;
  PipelineSetup setup;  // resolved: the scene's [pipeline] over the defaults
  TechTable tech;       // resolved: the scene's [tech] over the defaults
  EnergyTable energy = EnergyTable::defaults();  // resolved [tech.energy]
};

// The file's SHA-1 and size; throws InputError if it cannot be read.
InputDigest digest_file(const std::string& role, const std::string& path);

// Joins argv into one line ("texsim" + arguments), quoting arguments that need it.
std::string command_line(int argc, const char* const* argv);

// report.json's "provenance" object.
nlohmann::ordered_json provenance_json(const Provenance& p);
// report.md's provenance section.
void provenance_markdown(std::ostream& md, const Provenance& p);

}  // namespace texsim
