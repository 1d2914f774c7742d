#pragma once
// Where the module finds libtexsim_oiio.so: the texsim binary looks beside itself
// (/proc/self/exe), which in Python is the interpreter, so the module points the loader at the
// plugin beside the module instead (TEXSIM_OIIO_PLUGIN, unless the user set it).

namespace texsim_py {

void point_at_oiio_plugin();

}  // namespace texsim_py
