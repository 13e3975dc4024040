"""What every layer needs, whatever the mechanism or robot: parameter validation and parameter
files, input and output files (YAML, TOML, Rerun, SDF text), interrupts and progress, the
variants and plugins, rotations, the compiled-code decorator, the output glossary."""
