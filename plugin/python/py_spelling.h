// The file pipeline's messages name the CLI's flags ("--depth normalized needs --depth-range
// NEAR,FAR"); a Python caller sets keywords. keywordSpelling rewrites a message in those:
// "depth='normalized' needs depth_range=(NEAR, FAR)". Flags with no keyword (--flat, --frames,
// --resume) are left as they are.
#pragma once
#include <string>

namespace obscura::python {

std::string keywordSpelling(const std::string& message);

} // namespace obscura::python
