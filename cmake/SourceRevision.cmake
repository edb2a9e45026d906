# Records the source revision (git commit, "-dirty" when the tree has changes) at configure
# time so that every result can name the code that produced it.
# A tree without .git (an image build, whose context leaves .git out; a tarball) is given its
# revision: -DCOMPACTION_SOURCE_REVISION=<commit> (docker/Dockerfile passes its build argument
# SOURCE_REVISION). Without either it is "unknown".
set(COMPACTION_SOURCE_REVISION "" CACHE STRING
  "Source revision recorded in the binaries; empty: read from git (\"unknown\" without .git)")
if(COMPACTION_SOURCE_REVISION)
  return()
endif()
find_package(Git QUIET)
set(COMPACTION_SOURCE_REVISION "unknown")
if(GIT_FOUND AND EXISTS ${CMAKE_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _rev
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE _rc)
  if(_rc EQUAL 0 AND _rev)
    execute_process(COMMAND ${GIT_EXECUTABLE} status --porcelain --untracked-files=no
      WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE _dirty
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    set(COMPACTION_SOURCE_REVISION "${_rev}")
    if(_dirty)
      set(COMPACTION_SOURCE_REVISION "${_rev}-dirty")
    endif()
  endif()
endif()

# Configure again when the commit or the index changes, so the recorded revision never goes
# stale across commits (a build after `git commit` re-runs this file).
if(EXISTS ${CMAKE_SOURCE_DIR}/.git/HEAD)
  set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
    ${CMAKE_SOURCE_DIR}/.git/HEAD ${CMAKE_SOURCE_DIR}/.git/index)
  file(READ ${CMAKE_SOURCE_DIR}/.git/HEAD _head)
  if(_head MATCHES "^ref: ([^\n]+)")
    if(EXISTS ${CMAKE_SOURCE_DIR}/.git/${CMAKE_MATCH_1})
      set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
        ${CMAKE_SOURCE_DIR}/.git/${CMAKE_MATCH_1})
    endif()
  endif()
endif()
