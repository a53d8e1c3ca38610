// Following a search from its folder in the workbench: the reads of its files on a thread
// of their own (never in a frame), and the search as the optimize panel shows it.
#pragma once

#include <string>

#include "workbench_state.hpp"
#include "worker.hpp"

namespace fird::ui {

// Follows `dir` from now on (made absolute; a job folder before its search begins is
// waited for), in place of the folder followed before.
void follow_folder(WorkbenchState& state, const std::string& dir);
void stop_following(WorkbenchState& state);

// Called every frame: takes a finished read, and starts the next once `now_s` (ImGui time)
// is due (about every second), until the search has ended.
void poll_followed_folder(FolderFollow& follow, double now_s);

// Whether the followed search has ended and its end has been read.
bool followed_search_ended(const FolderFollow& follow);

// The followed search as the panel draws a search: running until search.json is there.
SearchProgress followed_progress(const FollowedSearch& search);

} // namespace fird::ui
