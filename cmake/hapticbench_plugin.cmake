# hapticbench_add_plugin(NAME SOURCE...): a renderer plugin, a shared
# module named NAME.so that links hapticbench::renderer and exports only its
# entry point (HAPTICBENCH_PLUGIN, hapticbench/plugin.h); the libraries it
# links stay inside it. Installed with the package (find_package(hapticbench))
# and used by the build itself for its test plugins.
function(hapticbench_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  target_link_libraries(${name} PRIVATE hapticbench::renderer)
  target_compile_features(${name} PRIVATE cxx_std_20)
  set_target_properties(${name} PROPERTIES PREFIX "" CXX_VISIBILITY_PRESET hidden
                                           VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${name} PRIVATE -Wl,--exclude-libs,ALL)
endfunction()
