#pragma once
// How a block's operations map onto operators.
//  Spatial: one operator instance per operation of the data-flow graph, fully pipelined:
//           II = 1, latency = critical path, area = all operators.
//  Shared:  one operator of each kind the block uses, time-multiplexed (a compact FPGA block,
//           or the ALU of a shader core): II = max over kinds of ops of that kind, latency =
//           critical path + II - 1, area = one operator per kind used.
namespace texsim {

class ConfigReader;

enum class Datapath { Spatial, Shared };
// Key `datapath` ("spatial" | "shared") of a block's table.
Datapath parse_datapath(const ConfigReader& r, Datapath def);
const char* datapath_name(Datapath d);

}  // namespace texsim
