"""Cuts the tables of bench/report out of one Google Benchmark JSON run (times in us).

Usage: python3 bench/report_tables.py DIR   (reads DIR/bench.json, writes DIR/<table>.csv)
"""
import csv
import json
import sys

SCALE = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}


def us(run):
    """Time per call, or per item where the benchmark processes items (the batched kernels)."""
    if "items_per_second" in run:
        return 1e6 / run["items_per_second"]
    return run["real_time"] * SCALE[run["time_unit"]]


def num(x):
    """Counters that count things print as integers."""
    return int(x) if isinstance(x, float) and x.is_integer() else x


def facets(r):
    """The output's facets (cgal_quickhull: its triangles), for time per output facet."""
    return num(r.get("facets", r.get("triangles", "")))


def per_facet_ns(r):
    f = facets(r)
    return round(us(r) * 1e3 / f, 2) if f else ""


def per_work_ns(r):
    """Time per unit of the overlay's work, input edges plus output facets (osm_prepared rows)."""
    return round(us(r) * 1e3 / (r["input_edges"] + r["facets"]), 2) if "input_edges" in r else ""


def table1(p, r):
    return p[0] == "Table1" and [p[1], p[2], us(r), facets(r), per_facet_ns(r), per_work_ns(r)]


def degenerate(p, r):
    return p[0] == "Degenerate" and [p[1], p[2], us(r), facets(r), per_facet_ns(r), per_work_ns(r)]


def scaling(p, r):
    return p[0] == "Scaling" and [p[1], p[2], us(r), facets(r), int(p[1]) ** 2, per_facet_ns(r), per_work_ns(r)]


def speed_error(p, r):
    return p[0] == "SpeedError" and p[1:5] + [r["s_per_case"], r["max_rel_error"], r["exact_structure"]]


def isa_kernels(p, r):
    """The SoA kernels on every ISA (bench/isa_rows.hpp): ns per item (pair, sum or direction)."""
    return p[0] == "IsaKernels" and [p[1], p[2], p[3], us(r) * 1e3]


def near_parallel(p, r):
    return p[0] == "NearParallel" and [p[1], p[2], us(r), r["facets"], r["exact_facets"], r["euler_ok"],
                                       r["corrected"], r["max_rel_error"]]


def queries(p, r):
    wanted = p[0].endswith(("Distance", "Penetration", "Separation")) and p[0] != "MeshDistance"
    return wanted and [r["name"], us(r) * 1e3]


def mesh(p, r):
    return p[0] in ("MeshDistance", "MeshBuild") and "near_median_us" not in r and [
        "/".join(p[:3]), r.get("median_us", ""), r.get("max_us", ""), r.get("min_culled_pct", ""), us(r)]


BANDS = ("contact", "near", "far")


def mesh_bands(p, r):
    """The banded pose sets (MeshDistance and PointDistance rows with per-band counters)."""
    if "near_median_us" not in r:
        return False
    return [p[0], p[1], p[2], r["median_us"], r["max_us"]] + [r[f"{b}_{k}"] for b in BANDS for k in ("median_us", "max_us")] + [
        r.get("median_culled_pct", ""), r.get("bytes_per_triangle", "")]


def point_build(p, r):
    return p[0] == "PointBuild" and [p[1], p[2], us(r) / 1e3, r.get("bytes_per_point", "")]


def face_to_face(p, r):
    return p[0] == "FaceToFace" and [p[1], p[2], p[3], us(r) * 1e3, r.get("searched_share", ""), r.get("warm_share", "")]


def rounded(p, r):
    return p[0] == "Rounded" and [p[1], p[2], p[3], us(r) * 1e3, r.get("warm_share", "")]


def contact_patch(p, r):
    return p[0] == "ContactPatch" and [p[1], p[2], p[3], us(r) * 1e3, r.get("points", ""), r.get("warm_share", "")]


def time_of_impact(p, r):
    return p[0] == "TimeOfImpact" and [p[1], p[2], p[3], us(r) * 1e3, r.get("hits", ""), r.get("iterations", ""),
                                        r.get("dt_max", "")]


def trajectory(p, r):
    return p[0] == "Trajectory" and [p[1], p[2], us(r) * 1e3, r.get("contact_share", ""), r.get("warm_share", ""), r.get("searched_share", ""),
                                      r.get("median_us", ""), r.get("max_us", "")]


TABLES = {
    "table1": (["pair", "method", "time_us", "facets", "ns_per_facet", "ns_per_edge_or_facet"], table1),
    "degenerate": (["case", "method", "time_us", "facets", "ns_per_facet", "ns_per_edge_or_facet"], degenerate),
    "scaling": (["n", "method", "time_us", "facets", "pairs", "ns_per_facet", "ns_per_edge_or_facet"], scaling),
    "speed_error": (["set", "method", "precision", "isa", "s_per_case", "max_rel_error", "exact_structure"],
                    speed_error),
    "isa_kernels": (["kernel", "precision", "isa", "ns_per_item"], isa_kernels),
    "near_parallel": (["k", "method", "time_us", "facets", "exact_facets", "euler_ok", "corrected",
                       "max_rel_error"], near_parallel),
    "queries": (["benchmark", "time_ns"], queries),
    "mesh": (["benchmark", "median_us", "max_us", "min_culled_pct", "mean_us"], mesh),
    "trajectory": (["pair", "method", "ns_per_query", "contact_share", "warm_share", "searched_share", "median_us", "max_us"], trajectory),
    "face_to_face": (["family", "gap", "method", "ns_per_query", "searched_share", "warm_share"], face_to_face),
    "contact_patch": (["pair", "gap", "method", "ns_per_patch", "points", "warm_share"], contact_patch),
    "rounded": (["pair", "gap", "method", "ns_per_query", "warm_share"], rounded),
    "time_of_impact": (["pair", "motion", "method", "ns_per_motion", "hits", "iterations", "dt_max"], time_of_impact),
    "mesh_bands": (["set", "pair", "method", "median_us", "max_us"] + [f"{b}_{k}" for b in BANDS for k in ("median_us", "max_us")]
                   + ["median_culled_pct", "bytes_per_triangle"], mesh_bands),
    "point_build": (["cloud", "method", "build_ms", "bytes_per_point"], point_build),
}


def bands_markdown(directory):
    """Per pair and band: minksum against its peer (FCL, nanoflann), median and worst us; culling; memory."""
    rows = list(csv.DictReader(open(f"{directory}/mesh_bands.csv")))
    out = []
    # A shape against a mesh: FCL's faster solver per figure (its GJK or libccd on the triangles).
    for m in [r for r in rows if r["set"] == "MeshShapeDistance" and r["method"] == "fcl_obbrss_gjk"]:
        other = next(r for r in rows if r["set"] == m["set"] and r["pair"] == m["pair"] and r["method"] == "fcl_obbrss_libccd")
        faster = {k: (min(float(v), float(other[k])) if k.endswith("_us") else v) for k, v in m.items()}
        rows.append(dict(faster, method="fcl_obbrss"))
    for kind, peer, unit in (("MeshDistance", "fcl_obbrss", "triangle"), ("MeshShapeDistance", "fcl_obbrss", "triangle"),
                             ("PointDistance", "nanoflann", "point")):
        pairs = [r for r in rows if r["set"] == kind and r["method"] == "minksum"]
        if not pairs:
            continue
        out.append(f"| {kind} pair | band | minksum median | {peer} median | ratio | minksum worst | {peer} worst | "
                   f"worst ratio | minksum culled % (median) | bytes / {unit}: minksum, {peer} |")
        out.append("|---|---|---|---|---|---|---|---|---|---|")
        for m in pairs:
            f = next(r for r in rows if r["set"] == kind and r["pair"] == m["pair"] and r["method"] == peer)
            for band in ("all",) + BANDS:
                key = "" if band == "all" else band + "_"
                mm, fm = float(m[key + "median_us"]), float(f[key + "median_us"])
                mx, fx = float(m[key + "max_us"]), float(f[key + "max_us"])
                memory = ""
                if band == "all" and m["bytes_per_triangle"]:
                    memory = f"{float(m['bytes_per_triangle']):.0f}, {float(f['bytes_per_triangle']):.0f}"
                culled = f"{float(m['median_culled_pct']):.2f}" if band == "all" and m["median_culled_pct"] else ""
                out.append(f"| {m['pair'] if band == 'all' else ''} | {band} | {mm:.1f} | {fm:.1f} | {fm / mm:.1f}x | "
                           f"{mx:.1f} | {fx:.1f} | {fx / mx:.1f}x | {culled} | {memory} |")
        out.append("")
    builds = list(csv.DictReader(open(f"{directory}/point_build.csv")))
    if builds:
        out.append("| cloud | method | build [ms] | bytes / point |")
        out.append("|---|---|---|---|")
        for b in builds:
            out.append(f"| {b['cloud']} | {b['method']} | {float(b['build_ms']):.1f} | {float(b['bytes_per_point']):.0f} |")
    with open(f"{directory}/mesh_bands.md", "w") as f:
        f.write("\n".join(out) + "\n")


def by_method(path, first, second):
    """A CSV's rows by (first, second) column and then by method, with the keys in file order."""
    t, order = {}, []
    for r in csv.DictReader(open(path)):
        key = (r[first], r[second])
        if key not in t:
            t[key] = {}
            order.append(key)
        t[key][r["method"]] = r
    return t, order


def face_markdown(directory):
    """The FaceToFace table: one line per family and gap, the four methods side by side, the
    targets' ratios (FCL / cold >= 2, FCL / coherent >= 10, Bullet / coherent >= 5) and the
    exhaustive search's share."""
    t, order = by_method(f"{directory}/face_to_face.csv", "family", "gap")
    out = ["| family | gap | cold [ns] | coherent [ns] | fcl_gjk [ns] | bullet_gjk_warm [ns] | fcl / cold | fcl / coherent"
           " | bullet / coherent | searched (cold) | searched (coherent) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in order:
        m = t[key]
        ns = {k: float(m[k]["ns_per_query"]) for k in m}
        if len(ns) < 4:
            continue
        out.append(f"| {key[0]} | {key[1]} | {ns['minksum_cold']:.0f} | {ns['minksum_coherent']:.0f} | {ns['fcl_gjk']:.0f} |"
                   f" {ns['bullet_gjk_warm']:.0f} | {ns['fcl_gjk'] / ns['minksum_cold']:.2f}x |"
                   f" {ns['fcl_gjk'] / ns['minksum_coherent']:.2f}x | {ns['bullet_gjk_warm'] / ns['minksum_coherent']:.2f}x |"
                   f" {float(m['minksum_cold']['searched_share'] or 0):.4f} | {float(m['minksum_coherent']['searched_share'] or 0):.4f} |")
    with open(f"{directory}/face_to_face.md", "w") as f:
        f.write("\n".join(out) + "\n")


def rounded_markdown(directory):
    """The Rounded table: minksum cold and coherent against the faster of FCL's solvers and
    Bullet per pair and gap, and the ratios of the targets (fcl / cold >= 3, >= 1 where FCL has
    a closed form; fcl / coherent >= 10)."""
    t, order = by_method(f"{directory}/rounded.csv", "pair", "gap")
    out = ["| pair | gap | minksum [ns] | coherent [ns] | fcl (faster) [ns] | bullet [ns] | fcl / minksum"
           " | fcl / coherent | bullet / minksum | warm share |", "|---|---|---|---|---|---|---|---|---|---|"]
    for key in order:
        m = t[key]
        if len(m) < 5:
            continue
        ns = {k: float(m[k]["ns_per_query"]) for k in m}
        fcl = min(ns["fcl_gjk"], ns["fcl_libccd"])
        out.append(f"| {key[0]} | {key[1]} | {ns['minksum']:.0f} | {ns['minksum_coherent']:.0f} | {fcl:.0f} |"
                   f" {ns['bullet']:.0f} | {fcl / ns['minksum']:.2f}x | {fcl / ns['minksum_coherent']:.2f}x |"
                   f" {ns['bullet'] / ns['minksum']:.2f}x | {float(m['minksum_coherent']['warm_share'] or 0):.2f} |")
    with open(f"{directory}/rounded.md", "w") as f:
        f.write("\n".join(out) + "\n")


def patch_markdown(directory):
    """The ContactPatch table: minksum (cold and coherent) and Bullet's clipping per pair and
    contact, their ratios (target: bullet / minksum >= 5) and the mean points of each."""
    t, order = by_method(f"{directory}/contact_patch.csv", "pair", "gap")
    out = ["| pair | contact | minksum [ns] | coherent [ns] | bullet_clip [ns] | bullet / minksum | bullet / coherent"
           " | warm share | points: minksum, bullet |",
           "|---|---|---|---|---|---|---|---|---|"]
    for key in order:
        m = t[key]
        if len(m) < 3:
            continue
        a, c, b = (float(m[k]["ns_per_patch"]) for k in ("minksum", "minksum_coherent", "bullet_clip"))
        out.append(f"| {key[0]} | {key[1]} | {a:.0f} | {c:.0f} | {b:.0f} | {b / a:.2f}x | {b / c:.2f}x |"
                   f" {float(m['minksum_coherent']['warm_share']):.2f} |"
                   f" {float(m['minksum']['points']):.2f}, {float(m['bullet_clip']['points']):.2f} |")
    with open(f"{directory}/contact_patch.md", "w") as f:
        f.write("\n".join(out) + "\n")


def impact_markdown(directory):
    """The TimeOfImpact table: minksum, Bullet and FCL per pair and motion, the ratio to the
    fastest peer (target >= 5), the hit shares, minksum's GJK iterations and the peers' largest
    time difference from minksum's."""
    t, order = by_method(f"{directory}/time_of_impact.csv", "pair", "motion")
    out = ["| pair | motion | minksum [ns] | bullet_ccd [ns] | fcl_ccd [ns] | fastest peer / minksum | hits: minksum,"
           " bullet, fcl | minksum iterations | dt_max: bullet, fcl |", "|---|---|---|---|---|---|---|---|---|"]
    mesh = ["", "Against a mesh (FCL's naive solver: 10 sampled poses, not conservative):", "",
            "| scene | motion | minksum [ns] | fcl_ccd [ns] | fcl_ccd / minksum | hits: minksum, fcl |"
            " minksum iterations | dt_max: fcl |", "|---|---|---|---|---|---|---|---|"]
    tools = ["", "Tools of every size against the mesh (radius as a share of its diagonal): starting in contact"
             " (target <= 50 us) and starting clear, against the same tool's mesh distance at the clear start"
             " (target: the sweep within 2x of it):", "",
             "| tool | in contact [us] | clear [us] | distance at the clear start [us] | clear / distance |"
             " iterations: in contact, clear |", "|---|---|---|---|---|---|"]
    for key in order:
        m = t[key]
        if key[1].startswith("tool_") and len(m) == 3:
            c, s, d = (float(m[k]["ns_per_motion"]) / 1e3 for k in ("in_contact", "clear", "distance_at_clear_start"))
            tools.append(f"| {key[1][5:]} | {c:.1f} | {s:.1f} | {d:.1f} | {s / d:.2f}x |"
                         f" {float(m['in_contact']['iterations']):.1f}, {float(m['clear']['iterations']):.1f} |")
            continue
        if "bullet_ccd" not in m and len(m) == 2:
            a, f = (float(m[k]["ns_per_motion"]) for k in ("minksum", "fcl_ccd"))
            mesh.append(f"| {key[0]} | {key[1]} | {a:.0f} | {f:.0f} | {f / a:.2f}x | {float(m['minksum']['hits']):.3f},"
                        f" {float(m['fcl_ccd']['hits']):.3f} | {float(m['minksum']['iterations']):.1f} |"
                        f" {float(m['fcl_ccd']['dt_max']):.1e} |")
        if len(m) < 3:
            continue
        a, b, f = (float(m[k]["ns_per_motion"]) for k in ("minksum", "bullet_ccd", "fcl_ccd"))
        hits = ", ".join(f"{float(m[k]['hits']):.3f}" for k in ("minksum", "bullet_ccd", "fcl_ccd"))
        # The fastest peer among those that find minksum's hits: a peer that misses the
        # contacts is not a faster answer (FCL's turning advancement once reported none).
        found = [x for x, k in ((b, "bullet_ccd"), (f, "fcl_ccd"))
                 if abs(float(m[k]["hits"]) - float(m["minksum"]["hits"])) <= 0.01]
        ratio = f"{min(found) / a:.2f}x" if found else "- (no peer finds the hits)"
        out.append(f"| {key[0]} | {key[1]} | {a:.0f} | {b:.0f} | {f:.0f} | {ratio} | {hits} |"
                   f" {float(m['minksum']['iterations']):.2f} | {float(m['bullet_ccd']['dt_max']):.1e},"
                   f" {float(m['fcl_ccd']['dt_max']):.1e} |")
    if len(mesh) > 5:
        out += mesh
    if len(tools) > 5:
        out += tools
    with open(f"{directory}/time_of_impact.md", "w") as f:
        f.write("\n".join(out) + "\n")


def main(directory):
    runs = json.load(open(directory + "/bench.json"))["benchmarks"]
    for name, (header, row) in TABLES.items():
        with open(f"{directory}/{name}.csv", "w", newline="") as f:
            out = csv.writer(f, lineterminator="\n")
            out.writerow(header)
            for r in runs:
                x = row(r["name"].split("/"), r)
                if x:
                    out.writerow([num(v) for v in x])
    bands_markdown(directory)
    face_markdown(directory)
    rounded_markdown(directory)
    patch_markdown(directory)
    impact_markdown(directory)


if __name__ == "__main__":
    main(sys.argv[1])
