# Checks the build's target graph, as `cmake --graphviz` draws it for a fresh configure of the
# repository (direct link dependencies between targets):
#  - only the command line (acdr_cli) links the benchmark library acdr_bench, besides the
#    bench's own programs and tests (BENCH_OWN);
#  - no engine target (ENGINE_TARGETS) reaches JSON, SQLite or a screen library, directly or
#    through what it links;
#  - the application layer (acdr_app) reaches neither the views (acdr_ui) nor a screen library;
#  - the training record (acdr_db) reaches no network library (sending is the app's business).
#   cmake -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -DENGINE_TARGETS=... -DBENCH_OWN=...
#         -P check_link_graph.cmake
cmake_minimum_required(VERSION 3.25)
foreach(var SOURCE_DIR WORK_DIR GENERATOR ENGINE_TARGETS BENCH_OWN)
  if(NOT ${var})
    message(FATAL_ERROR "${var} not set")
  endif()
endforeach()

# The graph of a fresh configure (the build tree under test is left alone).
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}/graph")
execute_process(
  COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -G "${GENERATOR}"
          "--graphviz=${WORK_DIR}/graph/targets.dot"
  RESULT_VARIABLE configured OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT configured EQUAL 0 OR NOT EXISTS "${WORK_DIR}/graph/targets.dot")
  message(FATAL_ERROR "configuring for the target graph failed:\n${log}")
endif()

# Edges: each line `"nodeA" -> "nodeB" ... // a -> b` names its targets in the comment.
file(STRINGS "${WORK_DIR}/graph/targets.dot" lines REGEX "// .* -> ")
set(targets "")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "^.*// (.*) -> (.*)$" "\\1;\\2" edge "${line}")
  list(GET edge 0 from)
  list(GET edge 1 to)
  string(MAKE_C_IDENTIFIER "${from}" id)
  list(APPEND "deps_${id}" "${to}")
  list(APPEND targets "${from}")
endforeach()
list(REMOVE_DUPLICATES targets)
list(LENGTH lines edges)
if(edges LESS 10)
  message(FATAL_ERROR "the target graph has only ${edges} edges: not the graph of this project")
endif()

# Everything `target` reaches through its links, into `out`.
function(reachable target out)
  set(seen "")
  set(todo "${target}")
  while(todo)
    list(POP_FRONT todo t)
    string(MAKE_C_IDENTIFIER "${t}" id)
    foreach(d IN LISTS deps_${id})
      if(NOT d IN_LIST seen)
        list(APPEND seen "${d}")
        list(APPEND todo "${d}")
      endif()
    endforeach()
  endwhile()
  set(${out} "${seen}" PARENT_SCOPE)
endfunction()

set(violations "")
set(screen "PkgConfig::OSMESA;PkgConfig::IMGUI;PkgConfig::GLFW;PkgConfig::STB;OpenGL::GL")
set(formats "nlohmann_json::nlohmann_json;SQLite::SQLite3;CURL::libcurl")

foreach(t IN LISTS targets)
  string(MAKE_C_IDENTIFIER "${t}" id)
  if("acdr_bench" IN_LIST deps_${id} AND NOT t STREQUAL "acdr_cli" AND NOT t IN_LIST BENCH_OWN)
    string(APPEND violations "  ${t} links acdr_bench (only the command line may)\n")
  endif()
endforeach()

foreach(t IN LISTS ENGINE_TARGETS)
  reachable("${t}" reached)
  foreach(lib IN LISTS formats screen)
    if(lib IN_LIST reached)
      string(APPEND violations "  engine target ${t} reaches ${lib}\n")
    endif()
  endforeach()
endforeach()

reachable(acdr_app reached)
if(NOT "acdr_engine" IN_LIST reached)
  string(APPEND violations "  acdr_app does not reach acdr_engine: is the graph complete?\n")
endif()
foreach(lib IN LISTS screen ITEMS acdr_ui acdr_cli acdr_bench)
  if(lib IN_LIST reached)
    string(APPEND violations "  acdr_app reaches ${lib} (the application layer has no screen)\n")
  endif()
endforeach()

reachable(acdr_db reached)
foreach(lib IN ITEMS acdr_net CURL::libcurl)
  if(lib IN_LIST reached)
    string(APPEND violations "  acdr_db reaches ${lib} (the record knows no network)\n")
  endif()
endforeach()

if(violations)
  message(FATAL_ERROR "the target graph breaks the layering:\n${violations}")
endif()
list(LENGTH targets count)
message(STATUS "target graph: ${count} targets, ${edges} links; layering holds")
