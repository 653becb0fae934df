# The reproduction report: every published number beside the project's value, with a status.


rule reproduction_report:
    input:
        parts=REPORT_PARTS,
        code=code_inputs("scripts/reproduction_report.py"),
    output:
        table("reproduction_report"),
    log:
        logfile("reproduction_report"),
    benchmark:
        bench("reproduction_report")
    message:
        "Joining {n} report parts into the reproduction report".format(n=len(REPORT_PARTS))
    script:
        "scripts/reproduction_report.py"


BOOK_INPUTS.append(table("reproduction_report"))
