# Fails when a source file under engine/ includes what the engine must not know: JSON
# (nlohmann), SQLite, a screen (GL, GLFW, Dear ImGui, OSMesa), or a header of a layer above it.
# The engine is the simulation alone; file formats, the record and the views sit above it.
#   cmake -DSOURCE_DIR=<repository> -P check_engine_includes.cmake
cmake_minimum_required(VERSION 3.25)
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "SOURCE_DIR not set")
endif()

# What an include path must not match, and why (one reason per pattern).
set(forbidden
  "nlohmann/|json\\.hpp"                                       "JSON"
  "sqlite3"                                                    "SQLite"
  "^GL/|^GLES|^GLFW/|^KHR/|glcorearb|[Ii]m[Gg]ui|[Oo][Ss][Mm]esa" "a screen library (GL, GLFW, ImGui, OSMesa)"
  "^(assessment|scenarios|db|app|ui|cli|bench|verification|stress)/" "a layer above the engine"
)

file(GLOB_RECURSE sources LIST_DIRECTORIES false
  "${SOURCE_DIR}/engine/*.hpp" "${SOURCE_DIR}/engine/*.cpp"
  "${SOURCE_DIR}/engine/*.h" "${SOURCE_DIR}/engine/*.cc" "${SOURCE_DIR}/engine/*.inl")
list(LENGTH sources count)
if(count EQUAL 0)
  message(FATAL_ERROR "no sources found under ${SOURCE_DIR}/engine")
endif()

set(violations "")
foreach(file IN LISTS sources)
  file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[<\"]([^>\"]*)[>\"].*$" "\\1" path "${line}")
    set(i 0)
    list(LENGTH forbidden n)
    while(i LESS n)
      list(GET forbidden ${i} pattern)
      math(EXPR j "${i} + 1")
      list(GET forbidden ${j} what)
      if(path MATCHES "${pattern}")
        file(RELATIVE_PATH rel "${SOURCE_DIR}" "${file}")
        string(APPEND violations "  ${rel}: #include ${path} (${what})\n")
      endif()
      math(EXPR i "${i} + 2")
    endwhile()
  endforeach()
endforeach()

if(violations)
  message(FATAL_ERROR "engine/ includes what it must not know:\n${violations}")
endif()
message(STATUS "engine/: ${count} files, no JSON, SQLite, screen or upper-layer include")
