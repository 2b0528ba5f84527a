"""Load-case campaigns of `windrive run` jobs on dask.distributed (issue 15 §1).

A campaign file (TOML, docs/CAMPAIGNS.md) names a scene, the load cases (IEC 61400-1 DLC 1.2 wind bins ×
seeds weighted by a wind climate, free parameter grids, discrete events with a count per year) and the
channels to analyse. `python -m windrive_campaign run FILE` expands it into cases, runs each as one
`windrive run --analyse` subprocess on a dask cluster (the simulation and the analysis of its series —
statistics, DELs, LDD, gear and bearing ratings — in one process, src/analysis/case.rs) and writes one
result file per case, then one Parquet table per campaign. Modules, one job each:

- schema:   read and validate the campaign file (errors name file, key and line)
- climate:  Weibull/Rayleigh wind-bin probabilities, the IEC normal turbulence model
- cases:    expand a campaign into cases with stable ids; snapshot the scene
- runner:   one case on a worker: the `windrive run --analyse` subprocess, atomic result file
- store:    result files on disk and the campaign's Parquet table
- cluster:  LocalCluster, a running scheduler, or the SLURM profile
- driver:   submit, progress, resume, cost
- lifetime: the design life's damage sums, DELs, shares and LDD from the table (issue 15 §2)
- report:   `report`: lifetime.csv/.json/_ldd.csv, the bar chart and the printed table
- gears:    [gears]: the gear table each case's teeth are rated with; bearings: [bearings] likewise
- paper_data: the paper's Tables 6 and 7 (docs/SOURCES.md §Paper), transcribed
- paper:    `paper`: our gear damage per wind speed x TI cell beside the paper's, η, the shape checks
- paper_report: `paper`: the tables as CSV/Markdown, the η heat maps, the JSON summary, the printout
"""
