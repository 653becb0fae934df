# Rules of the mocap part (see rules/common.smk for helpers).
