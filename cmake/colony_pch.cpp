// The source of the precompiled-header targets (colony_plugin_pch, colony_test_pch in
// CMakeLists.txt): CMake compiles cmake/colony_pch.h for them; this file adds nothing.
