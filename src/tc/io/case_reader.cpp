#include "tc/io/case_reader.hpp"
