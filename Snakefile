# isorock workflow: rocking of rigid blocks on isolated bases, from records to the report.
#
#   snakemake --cores 2                                  # default config/config.yaml
#   snakemake --cores 2 --configfile config/ci.yaml      # reduced grids over ../shared/records
#   snakemake --cores 2 --configfile config/paper.yaml   # the paper's full grids (~10-13 min)
#   snakemake --report report.html                       # self-contained report of the last run
#   isorock report --cores 2                             # both, with the workflow profile
#
# The rules only wire together the functions of isorock.pipeline (one per rule); the HDF5 layout of
# results/isorock.h5 is described in isorock.store. A --configfile given on the command line is merged
# over config/config.yaml (mappings key by key, lists replaced); paths in it are relative to the
# working directory.

import os
import sys

from snakemake.utils import min_version

from isorock.errors import IsorockError
from isorock.pipeline import apply_studies_default, validate_config
from isorock.control.config import user_assessment

min_version("8.0")


configfile: os.path.join(workflow.basedir, "config", "config.yaml")


# the example assessment of config/config.yaml is the default run's (its report's Assessment page): a
# --configfile other than config/config.yaml brings its own assessment section, or none
_default_cfg = os.path.realpath(os.path.join(workflow.basedir, "config", "config.yaml"))
_user_cfgs = [f for f in workflow.overwrite_configfiles if os.path.realpath(f) != _default_cfg]
if _user_cfgs:
    config["assessment"] = user_assessment(_user_cfgs)


# the one validator of isorock (schema, defaults, case names): a bad configuration stops here, in one line
try:
    # a --configfile with only records, isolation and assessment runs no paper study
    apply_studies_default(config, workflow.overwrite_configfiles)
    validate_config(config)
except IsorockError as _exc:
    sys.exit(f"isorock: error: {_exc}")


# the report opens with the results: a page written by rule report_tables (isorock.report.landing)
report: os.path.abspath("results/report/landing.rst")


include: "workflow/rules/common.smk"
include: "workflow/rules/records.smk"
include: "workflow/rules/pulses.smk"
include: "workflow/rules/assessment.smk"
include: "workflow/rules/store.smk"
include: "workflow/rules/report.smk"


rule all:
    input:
        final_targets(),
    default_target: True
