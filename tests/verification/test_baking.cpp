// Baking physics of the SPH solver (thesis 3.1.6, 3.3): filled in below.
#include <gtest/gtest.h>

#include "helpers.hpp"
