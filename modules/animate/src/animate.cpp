#include <opencv2/multicage/animate.hpp>
