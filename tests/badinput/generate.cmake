cmake_minimum_required(VERSION 3.25)
# Makes the inputs of the bad-input corpus that are too big to commit or cannot be
# committed (links, a rendered EXR): cmake -DGEN=<folder> -DNORI=<nori> -DDIR=<this folder>
# -P generate.cmake
file(MAKE_DIRECTORY ${GEN})

# 20000 nested <mesh> elements: a recursive parser without a depth limit overflows its stack.
string(REPEAT "<mesh type=\"obj\">" 20000 open)
string(REPEAT "</mesh>" 20000 close)
file(WRITE ${GEN}/nested.xml "<scene>${open}${close}</scene>\n")

# File names with a part longer than the 255 characters a file system allows.
string(REPEAT "a" 300 long)
file(WRITE ${GEN}/include-long-name.xml "<scene><include filename=\"${long}.xml\"/></scene>\n")

# Links that point at each other.
file(REMOVE ${GEN}/loop-a.xml ${GEN}/loop-b.xml)
file(CREATE_LINK loop-b.xml ${GEN}/loop-a.xml SYMBOLIC)
file(CREATE_LINK loop-a.xml ${GEN}/loop-b.xml SYMBOLIC)
file(WRITE ${GEN}/include-loop.xml "<scene><include filename=\"loop-a.xml\"/></scene>\n")

# An EXR image, passed where a scene file belongs: rendered by nori itself.
execute_process(COMMAND ${NORI} --no-progress -o ${GEN}/image ${DIR}/valid.xml
                RESULT_VARIABLE status OUTPUT_QUIET ERROR_VARIABLE output)
if(NOT status EQUAL 0)
    message(FATAL_ERROR "could not render ${DIR}/valid.xml: ${output}")
endif()

# A Loop subdivision surface of 2000 triangles at level 8: 1.3·10⁸ triangles, more than
# the pbrt-v4 importer builds.
string(REPEAT "0 1 2 " 2000 indices)
file(WRITE ${GEN}/huge-subdivision.pbrt "WorldBegin\n# 2000 triangles, 8 levels\nShape \"loopsubdiv\" \"integer levels\" [8]\n  \"point3 P\" [0 0 0 1 0 0 0 1 0]\n  \"integer indices\" [${indices}]\n")
