/* "RTTest offline" (Thesis 3.2): build the tree once and save it with the
 * scene as a .kdt (layout in scene/kdt_format.h; the engine adopts the
 * arrays of a loaded file without rebuilding). */
#include "kd_build.h"
#include "kdt_format.h"
#include "rtt/optimized.h"

bool rtt_optimized_bake(const rtt_scene *scene, const rtt_engine_options *opt, const char *path, rtt_error *err)
{
    kd_build_options build = {.max_depth = opt ? opt->max_tree_depth : 0, .threads = opt ? opt->threads : 0};
    kd_tree tree;
    if (!kd_build_sah(scene, &build, &tree, err)) return false;
    /* engine_optimized.c asserts that kd_tree.h's records are the file's */
    const rtt_baked_tree view = {
        .nodes = (kdt_node *)tree.nodes,
        .leaves = (kdt_leaf *)tree.leaves,
        .records = (kdt_triangle *)tree.triangles,
        .node_count = tree.node_count,
        .leaf_count = tree.leaf_count,
        .record_count = tree.triangle_count,
        .bounds = tree.bounds,
        .info = tree.info,
    };
    bool ok = rtt_kdt_write(path, scene, &view, err);
    kd_tree_free(&tree);
    return ok;
}
