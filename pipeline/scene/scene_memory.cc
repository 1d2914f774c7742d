#include "pipeline/scene/scene_memory.h"

#include <atomic>

namespace texsim {

namespace {
std::atomic<uint64_t> g_limit{UINT64_MAX};
}  // namespace

void set_scene_memory_limit(uint64_t bytes) { g_limit.store(bytes); }
uint64_t scene_memory_limit() { return g_limit.load(); }

}  // namespace texsim
