# cmake -DDIR=<Mdir> -DPREFIX=<Vtop> -P TexsimVerilatorIncluder.cmake: writes DIR/PREFIX__all.cpp,
# which includes every C++ file Verilator wrote for the model, so the build compiles one
# translation unit whose name is known before verilation.
file(GLOB sources RELATIVE ${DIR} ${DIR}/${PREFIX}*.cpp)
list(REMOVE_ITEM sources ${PREFIX}__all.cpp)
list(SORT sources)
set(text "// generated — do not edit: the C++ of the Verilated model ${PREFIX}\n")
foreach(s ${sources})
  string(APPEND text "#include \"${s}\"\n")
endforeach()
file(WRITE ${DIR}/${PREFIX}__all.cpp "${text}")
