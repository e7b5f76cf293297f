/*
 * no_heap.c - the images have no heap. newlib-nano's printf core references
 * malloc (for the growing strings of asprintf), which the design's
 * snprintf into a fixed buffer (design/, on the float images) never takes;
 * this _sbrk refuses every request, so a malloc would return NULL and
 * never take RAM from the stack.
 */
#include <errno.h>
#include <stddef.h>

void *_sbrk(ptrdiff_t incr);

void *_sbrk(ptrdiff_t incr)
{
    (void)incr;
    errno = ENOMEM;
    return (void *)-1;
}
