"""The batch workflow's population table: one row per pair from its status file and, for a matched pair, its
ffd-match report; written as CSV and JSON, with a summary picture (matplotlib)."""
import csv
import json
import math
import os
import statistics

# The table's columns, in order; the first five are the workflow's contract.
COLUMNS = ["id", "status", "seconds", "mean_directed_distance", "min_det_jacobian",
           "mean_directed_distance_before", "hausdorff_directed_distance", "max_det_jacobian",
           "non_converged_inverse_vertices", "match_seconds", "max_rss_mb", "attempt", "host", "method", "source",
           "target"]


def read_row(status_path):
    """One row of the table from a pair's status file and, if it matched, its report."""
    with open(status_path) as status_file:
        status = json.load(status_file)
    row = {column: None for column in COLUMNS}
    for key in ("id", "status", "seconds", "max_rss_mb", "attempt", "host", "source", "target"):
        row[key] = status.get(key)
    if status["status"] == "ok":
        with open(status["report"]) as report_file:
            report = json.load(report_file)
        row.update({
            "mean_directed_distance": report["distance_after"]["mean_directed"],
            "mean_directed_distance_before": report["distance_before"]["mean_directed"],
            "hausdorff_directed_distance": report["distance_after"]["hausdorff_directed"],
            "min_det_jacobian": report["min_jacobian_determinant"],
            "max_det_jacobian": report["max_jacobian_determinant"],
            "non_converged_inverse_vertices": report["non_converged_inverse_vertices"],
            "match_seconds": report["seconds"]["total"],
            "method": report["method"],
        })
    return row


def read_table(csv_path):
    """The rows of a population table written by write_population()."""
    with open(csv_path, newline="") as table:
        return list(csv.DictReader(table))


def summarize(rows):
    """Counts and the spread of time, memory and accuracy over the matched pairs."""
    matched = [row for row in rows if row["status"] == "ok"]
    summary = {"pairs": len(rows), "ok": len(matched), "failed": len(rows) - len(matched),
               "failed_ids": [row["id"] for row in rows if row["status"] != "ok"]}
    for key in ("seconds", "max_rss_mb", "mean_directed_distance", "min_det_jacobian"):
        values = [row[key] for row in matched if row[key] is not None]
        if values:
            summary[key] = {"min": min(values), "median": statistics.median(values), "max": max(values)}
    return summary


def write_population(status_paths, csv_path, json_path, png_path):
    rows = [read_row(path) for path in status_paths]
    with open(csv_path + ".partial", "w", newline="") as table:
        writer = csv.DictWriter(table, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows({k: ("" if v is None else v) for k, v in row.items()} for row in rows)
    os.replace(csv_path + ".partial", csv_path)
    with open(json_path + ".partial", "w") as document:
        json.dump({"summary": summarize(rows), "pairs": rows}, document, indent=1)
        document.write("\n")
    os.replace(json_path + ".partial", json_path)
    plot_population(rows, png_path)


def plot_population(rows, png_path):
    """Three panels: distance before/after per pair, min det J per pair, time per pair; failures listed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    matched = [row for row in rows if row["status"] == "ok"]
    figure, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    positions = range(len(matched))
    axes[0].plot(positions, [row["mean_directed_distance_before"] for row in matched], "o", label="before")
    axes[0].plot(positions, [row["mean_directed_distance"] for row in matched], "o", label="after")
    axes[0].set(xlabel="matched pair", ylabel="mean directed distance", title="distance target -> source")
    axes[0].legend()
    axes[1].plot(positions, [row["min_det_jacobian"] for row in matched], "o")
    axes[1].axhline(0.0, color="red", linewidth=1)
    axes[1].set(xlabel="matched pair", ylabel="min det J", title="folding (min det J <= 0)")
    seconds = [row["seconds"] for row in matched]
    axes[2].hist(seconds, bins=max(1, min(30, int(math.sqrt(len(seconds)) + 1))))
    axes[2].set(xlabel="seconds per pair", ylabel="pairs", title="time")
    failed_ids = ", ".join(row["id"] for row in rows if row["status"] != "ok")
    title = f"{len(rows)} pairs: {len(matched)} matched, {len(rows) - len(matched)} failed"
    figure.suptitle(title + (f" ({failed_ids[:80]})" if failed_ids else ""))
    figure.tight_layout()
    figure.savefig(png_path + ".partial.png", dpi=80)
    plt.close(figure)
    os.replace(png_path + ".partial.png", png_path)
