#include "tc/fem/assembler.hpp"
