# Warnings are errors for our own code; third-party headers come in as SYSTEM.
# -Wmissing-field-initializers is off: C++20 designated initializers for Vulkan
# create-infos deliberately leave the other members value-initialized.
function(fird_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual -Wconversion
    -Wno-sign-conversion -Wno-missing-field-initializers -Werror)
endfunction()
