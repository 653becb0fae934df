# Rules of the nonlinear part (see rules/common.smk for helpers).
