// The project's version and the git commit the binary was built from (generated at build time:
// cmake/version.cmake writes build/<preset>/generated/version.cpp); recorded in every output's
// provenance.
#pragma once

namespace flipflux {
const char* version_string();  ///< the project version, e.g. "0.1.0"
const char* git_commit();      ///< the git commit the binary was built from ("unknown" outside git)
}  // namespace flipflux
