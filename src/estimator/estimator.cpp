// Placeholder: the streaming Welch estimator is being written (issue 4).
#include "slidespec/estimator.hpp"
