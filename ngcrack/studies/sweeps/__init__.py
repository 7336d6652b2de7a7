"""Sweeps over element, mesh size, Poisson ratio and friction: one tidy row per run, errors, rates.

    df = sweep(scene, elements=["bdm", "peers"], maxh=[0.2, 0.1, 0.05], nu=[0.49],
               reference_maxh=0.025)
    with_rates(df)            # observed rates between consecutive meshes
    fitted_rates(df)          # least-squares rates per (scene, element, nu, friction, quantity)

The modules, each one idea, lower ones first:

    quantities   the error quantities (the paper's u1, u2, sigma_t1, sigma_nu), the
                 reference they are measured against, the closed-form errors
    results      the row schema and the CSV written one line per finished run
    cases        one run (a Case): the solve, its row, its memory
    executors    serial, worker processes, a Dask cluster
    grid         a sweep's request, checked before any run
    plan         sweep() itself: references first, resume, rows as they finish
    rates        convergence rates between meshes and fitted; Markdown tables
    measuring    the paper's way of measuring (element means against element means)

(`ngcrack.study`, the former name, still imports everything here.)
"""

from ...planar.quadrature import QUADRATURE_ORDER, quadrature_points
from ...shell.files import file_name_part
from .cases import MESH_OPTIONS, Case, run_case
from .executors import DASK_CONNECT_TIMEOUT
from .grid import check_friction_applies, warn_friction_not_applied
from .measuring import comparison_errors, element_means, mean_errors
from .plan import SweepError, check_sweep, sweep
from .quantities import (
    QUANTITIES,
    QUANTITY_LABELS,
    RATE_QUANTITIES,
    TIP_QUANTITIES,
    ZERO_FIELD,
    Reference,
    griffith_opening,
    k_error,
    opening_error,
    quantity_normal,
    sample_quantities,
    tip_columns,
)
from .rates import RATE_COLUMNS, fitted_rates, markdown_table, with_rates
from .results import KEY, KEY_DIGITS, ROW_COLUMNS, ROW_SCHEMA, ResultsFile, csv_line, read_results, scene_friction, typed

__all__ = [
    "Case", "DASK_CONNECT_TIMEOUT", "KEY", "KEY_DIGITS", "MESH_OPTIONS", "QUADRATURE_ORDER", "QUANTITIES",
    "QUANTITY_LABELS", "RATE_COLUMNS", "RATE_QUANTITIES", "ROW_COLUMNS", "ROW_SCHEMA", "Reference", "ResultsFile",
    "SweepError", "TIP_QUANTITIES", "check_friction_applies", "check_sweep", "ZERO_FIELD", "comparison_errors",
    "csv_line", "element_means", "file_name_part", "fitted_rates",
    "griffith_opening", "k_error", "markdown_table", "mean_errors", "opening_error", "quadrature_points",
    "quantity_normal", "read_results", "run_case", "sample_quantities", "scene_friction", "sweep", "tip_columns",
    "typed", "warn_friction_not_applied", "with_rates",
]
