# GLSL -> SPIR-V at build time, embedded as a C array header (glslangValidator --vn).
# The depfile makes a change to any #included file (e.g. fird_shared.h) rebuild the
# shader; a compile error fails the build with glslang's "ERROR: file:line:" message.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

# fird_add_shaders(TARGET <lib> SOURCES a.comp b.vert ... INCLUDE_DIRS dir...)
# Each shader foo.comp becomes <binary>/spv/foo_comp.h defining
#   const uint32_t fird_spv_foo_comp[].
function(fird_add_shaders)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES;INCLUDE_DIRS" ${ARGN})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${out_dir})
  set(include_flags)
  foreach(dir IN LISTS ARG_INCLUDE_DIRS)
    list(APPEND include_flags -I${dir})
  endforeach()
  set(headers)
  foreach(src IN LISTS ARG_SOURCES)
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(name ${src} NAME)
    string(REPLACE "." "_" var ${name})
    set(header ${out_dir}/${var}.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.3 ${include_flags}
              --depfile ${out_dir}/${var}.d --vn fird_spv_${var} -o ${header} ${abs}
      DEPENDS ${abs}
      DEPFILE ${out_dir}/${var}.d
      COMMENT "GLSL ${name}"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  add_custom_target(${ARG_TARGET}_spirv DEPENDS ${headers})
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_spirv)
  target_include_directories(${ARG_TARGET} PRIVATE ${out_dir})
endfunction()
