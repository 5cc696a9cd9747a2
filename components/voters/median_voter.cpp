// Registers the median voters (median_voter.hpp) in libkeel_stock: median of 3 as
// "MedianVoter" (profile MedianVoter.xml) and median of 5 as "MedianVoter5" (MedianVoter5.xml).
#include "median_voter.hpp"

KEEL_REGISTER_COMPONENT_AS(keel::components::MedianVoterN<3>, "MedianVoter")
KEEL_REGISTER_COMPONENT_AS(keel::components::MedianVoterN<5>, "MedianVoter5")
