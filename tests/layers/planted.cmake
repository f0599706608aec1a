# Negative control of the layering check: a copy of the tree with one upward include
# planted (geometry including the render layer's scene.h) must fail it, naming the file.
#   cmake -DROOT=<source> -DTABLE=<layers.txt> -DWORK=<dir> -DPYTHON=<python3> -P planted.cmake
file(REMOVE_RECURSE ${WORK})
file(COPY ${ROOT}/src ${ROOT}/include DESTINATION ${WORK})
file(APPEND ${WORK}/src/geometry/bvh.cpp "#include <nori/scene.h>\n")
execute_process(COMMAND ${PYTHON} ${ROOT}/scripts/check_layers.py ${WORK} ${TABLE}
                RESULT_VARIABLE status OUTPUT_VARIABLE output)
message("${output}")
if(status EQUAL 0 OR NOT output MATCHES "src/geometry/bvh.cpp:[0-9]+: area 'geometry' includes nori/scene.h of area 'render'")
    message(FATAL_ERROR "the planted upward include was not reported")
endif()
