/* PNG decoding with bounded memory (png_decode.c); used by png.c only. */
#ifndef LUMIS_IO_PNG_DECODE_H
#define LUMIS_IO_PNG_DECODE_H

/* The dimensions of a PNG in memory; 0 if its header is not readable. */
int lumis__png_decode_info(const unsigned char *data, int size, int *w, int *h);
/* The pixels as 16-bit RGB (grey replicated, alpha dropped, 8-bit values scaled exactly),
 * or NULL if the file is corrupt or asks for more memory than its dimensions justify.
 * Release with lumis__png_decode_free. */
unsigned short *lumis__png_decode_rgb16(const unsigned char *data, int size, int *w, int *h);
void lumis__png_decode_free(void *pixels);
/* Why the last call on this thread failed. */
const char *lumis__png_decode_error(void);

#endif
