# Rules of the section2 part (see rules/common.smk for helpers).
