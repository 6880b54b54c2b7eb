#pragma once

namespace flipflux {
const char* version_string();  ///< the project version, e.g. "0.1.0"
const char* git_commit();      ///< the git commit the binary was built from ("unknown" outside git)
}  // namespace flipflux
