# Rules of the linear part (see rules/common.smk for helpers).
