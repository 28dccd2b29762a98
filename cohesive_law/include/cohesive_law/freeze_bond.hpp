// Freeze-bond cohesive law (Polojärvi & Tuhkuri 2013, eqs 5-12).
// Placeholder: the law is being written in its own issue.
#pragma once

namespace cohesive_law {
const char* version();
}
