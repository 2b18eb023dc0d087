"""The paper's PCA studies, run as cases of ``coastmesh run`` (``[case] kind``).

Each module ``coastmesh.case.studies.<kind>`` provides ``parse_study(table, path_of)``
for the case file's ``[study]`` table and ``run_study(config, folder, stage)``,
which writes the study's rasters, tables and figures into ``folder``.
"""
