# docs/plugins.md is made by `cmake --build build --target docs` from the plugins' doc
# comments; this fails when the committed file differs from what the build makes now.
#   cmake -DNORI=<nori> -DSOURCE=<docs/plugins.md> -DWORK=<dir> -P plugins_md_current.cmake
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${NORI} --plugins-markdown ${WORK}/plugins.md RESULT_VARIABLE status)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "nori --plugins-markdown failed")
endif()
file(READ ${WORK}/plugins.md made)
file(READ ${SOURCE} committed)
if(NOT made STREQUAL committed)
    message(FATAL_ERROR "docs/plugins.md is stale: the doc comments say something else now. "
                        "Run `cmake --build build --target docs` and commit docs/plugins.md.")
endif()
