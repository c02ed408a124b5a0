// Progress for the command line: a one-line bar on stderr, as a renderer::ProgressCallback.
#pragma once

// Redrawn in place when it grows (41 redraws at most: a log that captures stderr keeps a short line).
// Always returns true (never cancels).
bool printProgress(double fraction);
