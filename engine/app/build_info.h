#pragma once
// What was built: the git commit of the sources (with "-dirty" when they had uncommitted
// changes at configure time), for the image's and the statistics' metadata.
namespace foton::app {
const char* git_commit();
}  // namespace foton::app
