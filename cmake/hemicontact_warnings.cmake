# INTERFACE target carrying the project's warning flags; linked PRIVATE and last.
add_library(hemicontact_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(hemicontact_warnings INTERFACE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
endif()
