# The commit the program is built from, for --version and every file's provenance. Run at
# configure time and again at every build (a commit made since the configure is seen), as
#   cmake -DSOURCE_DIR=... -DOUTPUT=.../source_commit.hpp [-DGIT=git] -P source_commit.cmake
# From git when the source is a git checkout and git is installed; otherwise from the source
# archive's .git_archival.txt, whose "commit:" line `git archive` fills in (export-subst in
# .gitattributes); otherwise "unknown". The header is rewritten only when it changes, so a
# build without a new commit recompiles nothing.
if(NOT DEFINED GIT)
  set(GIT git)
endif()
set(commit "")
set(origin "")
execute_process(COMMAND ${GIT} rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE commit RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(rc EQUAL 0 AND commit MATCHES "^[0-9a-f]+$")
  set(origin "read from git when built")
else()
  set(commit "")
  if(EXISTS ${SOURCE_DIR}/.git_archival.txt)
    file(STRINGS ${SOURCE_DIR}/.git_archival.txt line REGEX "^commit: *[0-9a-f]+$")
    if(line MATCHES "^commit: *([0-9a-f]+)$")
      string(SUBSTRING "${CMAKE_MATCH_1}" 0 12 commit)
      set(origin "from the source archive's .git_archival.txt")
    endif()
  endif()
endif()
if(NOT commit)
  set(commit "unknown")
  set(origin "neither a git checkout with git installed nor a git archive")
endif()
file(WRITE ${OUTPUT}.tmp "// Written by src/results/source_commit.cmake at build time.\n"
                         "#define ASTROJAX_GIT_COMMIT \"${commit}\"\n"
                         "#define ASTROJAX_COMMIT_ORIGIN \"${origin}\"\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)
