/* dtc_si_params_doc - keeps the table of the converter's SI inputs in the docs in step with their
 * description (dtc_si_params.h, dtc_si_params_markdown).
 *
 *   dtc_si_params_doc --check DOC   exit 0 when DOC's section is current, 1 (and why) when not
 *   dtc_si_params_doc --write DOC   rewrite DOC's section
 *
 * The section lies between the lines <!-- si-params:begin --> and <!-- si-params:end -->.
 * Exit status: 0 current or written; 1 stale, no markers or an I/O error; 2 bad usage. Host code. */
#define _POSIX_C_SOURCE 200809L
#include "dtc_si_params.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char BEGIN[] = "<!-- si-params:begin -->\n";
static const char END[] = "<!-- si-params:end -->";

static char *read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long len;
    if (f == NULL) {
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) == 0 && (len = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc((size_t)len + 1U)) != NULL) {
        *n = fread(buf, 1, (size_t)len, f);
        buf[*n] = '\0';
    }
    fclose(f);
    return buf;
}

int main(int argc, char **argv)
{
    const int write = argc == 3 && strcmp(argv[1], "--write") == 0;
    size_t n = 0, tn = 0;
    char *doc, *table = NULL, *b, *e;
    FILE *mem;
    int rc;
    if (argc != 3 || (!write && strcmp(argv[1], "--check") != 0)) {
        fprintf(stderr, "usage: dtc_si_params_doc --check|--write DOC\n");
        return 2;
    }
    doc = read_all(argv[2], &n);
    if (doc == NULL) {
        fprintf(stderr, "dtc_si_params_doc: %s: cannot read\n", argv[2]);
        return 1;
    }
    b = strstr(doc, BEGIN);
    e = b != NULL ? strstr(b, END) : NULL;
    if (e == NULL) {
        fprintf(stderr, "dtc_si_params_doc: %s: markers %s ... %s not found\n", argv[2], "<!-- si-params:begin -->", END);
        return 1;
    }
    b += strlen(BEGIN);
    mem = open_memstream(&table, &tn);
    if (mem == NULL || dtc_si_params_markdown(mem) != 0 || fclose(mem) != 0) {
        fprintf(stderr, "dtc_si_params_doc: cannot format the table\n");
        return 1;
    }
    if ((size_t)(e - b) == tn && memcmp(b, table, tn) == 0) {
        rc = 0;
    } else if (!write) {
        fprintf(stderr, "%s: the SI parameter table is stale (tools/config/dtc_si_params.h changed): run "
                        "build/host/bin/dtc_si_params_doc --write %s\n", argv[2], argv[2]);
        rc = 1;
    } else {
        FILE *f = fopen(argv[2], "wb");
        rc = f == NULL || fwrite(doc, 1, (size_t)(b - doc), f) != (size_t)(b - doc) ||
                     fwrite(table, 1, tn, f) != tn || fputs(e, f) < 0 || fclose(f) != 0
                 ? 1
                 : 0;
        if (rc != 0) {
            fprintf(stderr, "dtc_si_params_doc: %s: write failed\n", argv[2]);
        }
    }
    free(table);
    free(doc);
    return rc;
}
