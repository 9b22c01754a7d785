#include "drive_test_support.hpp"
