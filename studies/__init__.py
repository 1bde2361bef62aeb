"""lfdrom.studies: case catalogue, study files, runner, results store and reports."""
