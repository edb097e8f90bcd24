// The height accessors the traversal kernels read a grid through: one per storage of a whole grid, and one for
// a tiled grid. Not a header of its own: kernel_isas.h includes it in each instruction set's namespace, right
// before traversal_kernels.h; it therefore includes nothing and holds no pragma once.

// Height access in the hot loop, one kind per storage, each returning exactly HeightGrid::at's value. The
// walk reads a whole grid's cell flags and pyramid from the grid; a tiled grid's accessor (TiledHeights) brings
// its own.
struct Float32Heights {
    static constexpr bool kTiled = false;
    const float* h;
    int64_t width;
    float operator()(int64_t i, int64_t j) const { return h[j * width + i]; }
    void prefetch(int64_t i, int64_t j) const { __builtin_prefetch(h + (j * width + i)); }
};
struct Int16Heights {
    static constexpr bool kTiled = false;
    const int16_t* q;
    int64_t width;
    int32_t offset;
    double scale;
    float operator()(int64_t i, int64_t j) const { return decodeHeightCode(q[j * width + i], offset, scale); }
    void prefetch(int64_t i, int64_t j) const { __builtin_prefetch(q + (j * width + i)); }
};
// One metre per code: the decoded height is the integer itself (exact in float below 2^24 m).
struct Int16UnitHeights {
    static constexpr bool kTiled = false;
    const int16_t* q;
    int64_t width;
    int32_t offset;
    float operator()(int64_t i, int64_t j) const { return float(int32_t(q[j * width + i]) + offset); }
    void prefetch(int64_t i, int64_t j) const { __builtin_prefetch(q + (j * width + i)); }
};
// A tiled grid's (docs/architecture.md, "Tiled grids"): heights, cell flags and the lower pyramid levels come
// from the tile holding the cell, the levels above from the grid. One accessor serves one trace or one bundle of
// traces, during which nothing else reads the grid's tiles on that thread: it keeps the tile it last used, taken
// from the grid's per-thread memo (HeightGrid::tileOfCell), so a walk asks for a tile only when it moves to
// another, without touching a shared count. Values are the tile's, which holds them as the whole grid would:
// the walk takes the same steps and finds the same hits.
struct TiledHeights {
    static constexpr bool kTiled = true;
    const HeightGrid* grid;
    HeightGrid::PyramidView resident;  // levels above tileLevels
    int tileLevels;
    int64_t cellsX, cellsY;
    mutable const HeightTile* tile = nullptr;
    mutable int64_t x0 = 1, x1 = 0, y0 = 1, y1 = 0;  // the current tile's cells, inclusive

    // The tile holding cell (i, j). (These reads are forced inline: the walk reads through them at every cell.)
    const HeightTile& cellTile(int64_t i, int64_t j) const {
        if (i < x0 || i > x1 || j < y0 || j > y1) [[unlikely]]
            moveTo(i, j);
        return *tile;
    }
    // Out of line, so that the checks above inline into the walk.
    [[gnu::noinline]] void moveTo(int64_t i, int64_t j) const {
        tile = &grid->tileOfCell(i, j);
        x0 = tile->firstX();
        y0 = tile->firstY();
        x1 = x0 + tile->verticesX() - 2;
        y1 = y0 + tile->verticesY() - 2;
    }
    // Vertex (i, j): the current tile when it holds the vertex (it holds its cells' far edges too).
    float operator()(int64_t i, int64_t j) const {
        if (i < x0 || i > x1 + 1 || j < y0 || j > y1 + 1) [[unlikely]]
            return cellTile(std::min(i, cellsX - 1), std::min(j, cellsY - 1)).at(i, j);
        return tile->at(i, j);
    }
    void prefetch(int64_t, int64_t) const {}
    bool cellValid(int64_t i, int64_t j) const { return cellTile(i, j).cellValid(i, j); }
    int16_t code(int k, int64_t bi, int64_t bj) const {
        return k > tileLevels ? resident.code(k, bi, bj) : cellTile(bi << k, bj << k).maxCode(k, bi, bj);
    }
    int16_t minCode(int k, int64_t bi, int64_t bj) const {
        return k > tileLevels ? resident.minCode(k, bi, bj) : cellTile(bi << k, bj << k).minCode(k, bi, bj);
    }
};
