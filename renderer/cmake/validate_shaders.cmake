# cmake -P validate_shaders.cmake -DSHADER_DIR=<renderer/shaders> -DSOURCE_ROOT=<project root>
#   -DWORK_DIR=<scratch folder> -DGLSLANG=<glslangValidator> -DSTAMP=<file touched on success>
# Compiles every shader of every program in programs.cmake with each of its define sets, as the
# renderer prepends them, in one glslangValidator run. Errors name the shader file and line (through
# #line directives), once each however many define sets hit them.
cmake_minimum_required(VERSION 3.25)
include("${CMAKE_CURRENT_LIST_DIR}/shader_programs.cmake")
include("${SHADER_DIR}/programs.cmake")

file(RELATIVE_PATH origin "${SOURCE_ROOT}" "${SHADER_DIR}")
file(REMOVE_RECURSE "${WORK_DIR}")
set(inputs "")
set(count 0)
foreach(program IN LISTS SHADER_PROGRAMS)
  shader_define_sets(${program} sets)
  foreach(file IN LISTS SHADER_PROGRAM_${program}_FILES)
    resolve_shader_includes("${SHADER_DIR}" "${file}" "${origin}" body)
    set(n 0)
    foreach(set_ IN LISTS sets)
      string(SUBSTRING "${set_}" 1 -1 defines)
      string(REPLACE "|" "\n" defines "${defines}")
      # The stage comes from the extension: <program>/<n>.<file>, e.g. splat/3.splat.vert.
      set(input "${WORK_DIR}/${program}/${n}.${file}")
      file(WRITE "${input}" "#version 450 core\n#extension GL_GOOGLE_cpp_style_line_directive : require\n"
                            "${defines}${body}")
      string(REPLACE "\n" " " shown "${defines}")
      string(REPLACE "#define " "" shown "${shown}")
      set(DESCRIBE_${program}/${n}.${file} "${program} (${file}) with defines: ${shown}")
      list(APPEND inputs "${input}")
      math(EXPR n "${n} + 1")
      math(EXPR count "${count} + 1")
    endforeach()
  endforeach()
endforeach()

execute_process(COMMAND "${GLSLANG}" ${inputs}
                RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(result EQUAL 0)
  file(TOUCH "${STAMP}")
  return()
endif()

# glslangValidator prints each input's path, then its errors: keep each error once, and the define sets
# that hit errors. Semicolons stand aside while the output is a CMake list of lines.
string(REPLACE ";" "@semicolon@" output_lines "${output}")
string(REPLACE "\n" ";" lines "${output_lines}")
set(errors "")
set(failed "")
set(current "")
foreach(line IN LISTS lines)
  string(FIND "${line}" "${WORK_DIR}/" at)
  if(at EQUAL 0)
    string(LENGTH "${WORK_DIR}/" skip)
    string(SUBSTRING "${line}" ${skip} -1 current)
  elseif(line MATCHES "^ERROR: " AND NOT line MATCHES "compilation errors|Linking|No code generated")
    # As compilers write them, so editors jump there: /abs/path/file.glsl:12: error: message
    string(REGEX REPLACE "^ERROR: ([^:]+):([0-9]+): (.*)$" "${SOURCE_ROOT}/\\1:\\2: error: \\3"
           line "${line}")
    list(APPEND errors "${line}")
    list(APPEND failed "${current}")
  endif()
endforeach()
if(failed)
  list(REMOVE_DUPLICATES errors)
  list(REMOVE_DUPLICATES failed)
  list(LENGTH failed failures)
  list(GET failed 0 first)
  string(REPLACE ";" "\n" errors "${errors}")
  string(REPLACE "@semicolon@" ";" errors "${errors}")
  set(report "${errors}\nfirst failing: ${DESCRIBE_${first}}\n(sources in ${WORK_DIR})")
  set(summary "${failures} of ${count} compilations")
else()   # no error line: all it said
  set(report "${output}")
  set(summary "exit status ${result}")
endif()
# NOTICE, unlike FATAL_ERROR, leaves the lines as they are (no wrapping).
message(NOTICE "${report}")
message(FATAL_ERROR "GLSL validation failed: ${summary} (glslangValidator)")
