"""Running a study: plan the tasks that compute what the store lacks, run them on an executor, report progress.

- :mod:`studies.run.runner`: :func:`~studies.run.runner.run_study`;
- :mod:`studies.run.executors`: this process, local processes or a Dask cluster;
- :mod:`studies.run.progress`: progress lines and bar, and the reporters the tasks use.
"""
