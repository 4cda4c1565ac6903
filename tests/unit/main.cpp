// The Catch2 runner for every unit test. Test cases live next to the layer they test.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
