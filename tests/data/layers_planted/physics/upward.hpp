// A planted fault for the test `layers_planted`: physics (rank 1) including a command (app,
// rank 6) must be refused by tests/check_layers.cmake.
#pragma once
#include "app/commands.hpp"
