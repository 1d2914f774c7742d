#include "pipeline/texture/stages/lighting_stage.h"

namespace texsim {

void LightingStage::rows(StageReport& r, std::vector<BlockUse>& out) const {
  if (effect_.has_normal_unit()) {
    const NormalUnit& n = effect_.normal_unit();
    r.add(out, n.name(), n.arithmetic(), n.timing(r.tech), normal_ops_);
  }
  if (effect_.has_terrain_normal()) {
    const TerrainNormalUnit& n = effect_.terrain_normal();
    r.add(out, n.name(), n.arithmetic(), n.timing(r.tech), normal_ops_);
  }
  const BlinnPhongShader& sh = effect_.shader();
  r.add(out, sh.name(), sh.arithmetic(), sh.timing(r.tech), shader_ops_);
}

}  // namespace texsim
