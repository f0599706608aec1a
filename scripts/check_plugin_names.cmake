cmake_minimum_required(VERSION 3.25)
# Checks the names the plugin files register before anything is compiled, so that a
# mistake is reported in seconds instead of after the build (the programs check again
# when they start: NoriObjectFactory::checkRegistry):
#   cmake -DSOURCES_FILE=<list> -DSHIPPED_LIST=plugins/builtin/shipped.txt
#         [-DSTAMP=<file>] -P check_plugin_names.cmake
# SOURCES_FILE lists the plugin files, one absolute path a line. It is an error when two
# of our files, or two of yours, register one name for one kind of plugin (both files are
# named); a file of yours that registers the name of one of ours replaces ours, which is
# said in one line; a file that registers nothing is a warning (a warp.cpp or helpers may
# rightly do so). STAMP, when given, is touched on success. CMakeLists.txt runs it when
# it configures and again, as a step of the build, whenever a plugin file changes.

file(STRINGS ${SOURCES_FILE} NORI_CHECK_SOURCES)
file(STRINGS ${SHIPPED_LIST} shipped_lines REGEX "^[^#]")
get_filename_component(shipped_root ${SHIPPED_LIST} DIRECTORY)
set(NORI_CHECK_SHIPPED "")
foreach(line IN LISTS shipped_lines)
    string(STRIP "${line}" line)
    cmake_path(ABSOLUTE_PATH line BASE_DIRECTORY ${shipped_root} NORMALIZE OUTPUT_VARIABLE file)
    list(APPEND NORI_CHECK_SHIPPED "${file}")
endforeach()

# The kind of plugin a base class makes (the base classes of include/nori/ and of Nori 2
# courses); a class whose base is not listed conflicts with a name of any kind.
set(kinds_of_bases
    "BSDF=bsdf" "NestedBSDF=bsdf" "SurfaceWrapperBSDF=bsdf" "Integrator=integrator"
    "PathTracer=integrator" "DirectLighting=integrator" "Emitter=emitter" "Mesh=mesh"
    "Shape=mesh" "CompoundShape=mesh" "Medium=medium" "PhaseFunction=phase"
    "Texture=texture" "Camera=camera" "Sampler=sampler" "ReconstructionFilter=rfilter"
    "NoriObject=test")

# `text` without its comments, so that a registration in a comment does not count.
function(nori_strip_comments text output)
    set(result "")
    while(TRUE)
        string(FIND "${text}" "/*" open)
        if(open EQUAL -1)
            break()
        endif()
        string(SUBSTRING "${text}" 0 ${open} before)
        string(APPEND result "${before}")
        string(SUBSTRING "${text}" ${open} -1 text)
        string(FIND "${text}" "*/" close)
        if(close EQUAL -1)
            set(text "")
            break()
        endif()
        math(EXPR close "${close} + 2")
        string(SUBSTRING "${text}" ${close} -1 text)
    endwhile()
    string(APPEND result "${text}")
    string(REGEX REPLACE "//[^\n]*" "" result "${result}")
    set(${output} "${result}" PARENT_SCOPE)
endfunction()

# "plugins/course/ao.cpp" from an absolute path, for messages.
function(nori_short_path path output)
    string(REGEX REPLACE "^.*/(plugins|tests)/" "\\1/" short "${path}")
    set(${output} "${short}" PARENT_SCOPE)
endfunction()

set(registered "") # entries "kind|name|file"
set(errors "")
foreach(source IN LISTS NORI_CHECK_SOURCES)
    file(READ ${source} text)
    nori_strip_comments("${text}" code)
    nori_short_path(${source} short)
    # One of our files always starts with its doc comment: one that does not was
    # overwritten (a course file copied over ours), and would fail -Werror and the doc test.
    list(FIND NORI_CHECK_SHIPPED ${source} ours)
    if(NOT ours EQUAL -1 AND NOT text MATCHES "^/\\*\n \\* [a-z_0-9]+ ")
        string(APPEND errors "\n  ${short} is one of ours (plugins/builtin/shipped.txt) but does not "
                             "start with its doc comment: if a file of yours was copied over it, "
                             "move yours to plugins/course/ and restore ours with "
                             "'git checkout -- ${short}'")
    endif()
    string(REGEX MATCHALL "NORI_REGISTER_(CLASS|ALIAS)[ \t\r\n]*\\([ \t\r\n]*[A-Za-z_0-9]+[ \t\r\n]*,[ \t\r\n]*\"[^\"]*\""
           registrations "${code}")
    if(NOT registrations)
        message(WARNING "${short} registers no plugin (no NORI_REGISTER_CLASS): it is compiled "
                        "into the programs, but no scene can name anything in it (right for a "
                        "warp.cpp or helpers)")
        continue()
    endif()
    foreach(registration IN LISTS registrations)
        string(REGEX REPLACE ".*\\([ \t\r\n]*([A-Za-z_0-9]+).*" "\\1" class "${registration}")
        string(REGEX REPLACE ".*\"([^\"]*)\"$" "\\1" name "${registration}")
        set(kind "")
        string(REGEX MATCH "(class|struct)[ \t\r\n]+${class}[^{;]*:[ \t\r\n]*(public[ \t\r\n]+)?(nori::)?([A-Za-z_]+)"
               declaration "${code}")
        if(declaration)
            set(base "${CMAKE_MATCH_4}")
            foreach(pair IN LISTS kinds_of_bases)
                if(pair MATCHES "^${base}=(.*)$")
                    set(kind "${CMAKE_MATCH_1}")
                endif()
            endforeach()
        endif()
        list(APPEND registered "${kind}|${name}|${source}")
    endforeach()
endforeach()

# Every pair of registrations of one name by two files, of one kind (or of an unknown one).
list(LENGTH registered count)
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
    list(GET registered ${i} first)
    string(REPLACE "|" ";" first "${first}")
    list(GET first 0 kind_a)
    list(GET first 1 name_a)
    list(GET first 2 file_a)
    math(EXPR next "${i} + 1")
    if(next GREATER last)
        break()
    endif()
    foreach(j RANGE ${next} ${last})
        list(GET registered ${j} second)
        string(REPLACE "|" ";" second "${second}")
        list(GET second 0 kind_b)
        list(GET second 1 name_b)
        list(GET second 2 file_b)
        if(NOT name_a STREQUAL name_b OR file_a STREQUAL file_b)
            continue()
        endif()
        if(kind_a AND kind_b AND NOT kind_a STREQUAL kind_b)
            continue()
        endif()
        nori_short_path(${file_a} short_a)
        nori_short_path(${file_b} short_b)
        list(FIND NORI_CHECK_SHIPPED ${file_a} ours_a)
        list(FIND NORI_CHECK_SHIPPED ${file_b} ours_b)
        if(ours_a EQUAL -1 AND NOT ours_b EQUAL -1)
            message(STATUS "Your ${short_a} replaces our '${name_a}' (${short_b}); "
                           "'nori --builtin ${name_a}' uses ours")
        elseif(ours_b EQUAL -1 AND NOT ours_a EQUAL -1)
            message(STATUS "Your ${short_b} replaces our '${name_a}' (${short_a}); "
                           "'nori --builtin ${name_a}' uses ours")
        else()
            string(APPEND errors "\n  two files register one name: '${name_a}' is registered by "
                                 "${short_a} and by ${short_b}: "
                                 "rename one (the name in its NORI_REGISTER_CLASS), or remove "
                                 "the file you do not want")
        endif()
    endforeach()
endforeach()
if(errors)
    message(FATAL_ERROR "the plugin files are in conflict:${errors}")
endif()
if(DEFINED STAMP)
    file(TOUCH ${STAMP})
endif()
