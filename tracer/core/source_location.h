// Where an item was written in an input file, for messages.
#pragma once

namespace terracast {

// 1-based line and column; 0 when the item did not come from a file.
struct SourceLocation {
    int line = 0;
    int column = 0;
};

}  // namespace terracast
