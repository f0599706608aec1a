cmake_minimum_required(VERSION 3.25)
# Runs one case of the bad-input corpus: cmake -DNORI=<nori> -DCASE=<name>
# -DMANIFEST=<cases.txt> -DDIR=<its folder> -DGEN=<generated inputs> [-DSANITIZED=ON]
# -P run_case.cmake. Fails on a crash, a hang, another exit status, or a message without
# the expected text.
file(STRINGS ${MANIFEST} lines REGEX "^${CASE} \\| ")
list(LENGTH lines count)
if(NOT count EQUAL 1)
    message(FATAL_ERROR "${MANIFEST}: ${count} lines for case '${CASE}'")
endif()
# Fields by plain string search: the messages hold brackets, which list commands mangle.
set(rest "${lines} | ")
set(fields name status pattern arguments memory)
foreach(field IN LISTS fields)
    string(FIND "${rest}" " | " end)
    if(end EQUAL -1)
        set(${field} "")
    else()
        string(SUBSTRING "${rest}" 0 ${end} ${field})
        math(EXPR next "${end} + 3")
        string(SUBSTRING "${rest}" ${next} -1 rest)
    endif()
endforeach()

string(REPEAT "a" 300 long)
string(REPLACE "@DIR@" "${DIR}" arguments "${arguments}")
string(REPLACE "@GEN@" "${GEN}" arguments "${arguments}")
string(REPLACE "@LONG@" "${long}" arguments "${arguments}")
separate_arguments(arguments UNIX_COMMAND "${arguments}")
set(command ${NORI} --no-progress ${arguments})
if(memory)
    if(SANITIZED)
        # ASan and TSan reserve terabytes of address space, so a limit on it cannot be
        # used; their allocators fail large allocations instead (and new then throws
        # std::bad_alloc). TSan's other options (suppressions) are kept.
        set(limit "allocator_may_return_null=1:max_allocation_size_mb=${memory}")
        set(ENV{ASAN_OPTIONS} "${limit}")
        set(ENV{TSAN_OPTIONS} "$ENV{TSAN_OPTIONS}:${limit}")
    else()
        math(EXPR bytes "${memory} * 1048576")
        set(command prlimit --as=${bytes} ${command})
    endif()
endif()
execute_process(COMMAND ${command} RESULT_VARIABLE result OUTPUT_VARIABLE output
                ERROR_VARIABLE output TIMEOUT 120)
message("${output}")
if(NOT "${result}" STREQUAL "${status}")
    message(FATAL_ERROR "expected exit status ${status}, got '${result}'")
endif()
string(FIND "${output}" "${pattern}" found)
if(found EQUAL -1)
    message(FATAL_ERROR "the message does not contain: ${pattern}")
endif()
