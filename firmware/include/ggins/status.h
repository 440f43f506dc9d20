/**
 * @file status.h
 * @brief One status type for every firmware function (NASA cFE habit).
 *
 * Every firmware function returns gg_status_t; GG_OK is zero, every error is
 * non-zero. A function that returns an error leaves its state untouched.
 */
#ifndef GGINS_STATUS_H
#define GGINS_STATUS_H

typedef enum {
    GG_OK = 0,
    GG_ERR_NULL = 1,        /**< a required pointer was NULL */
    GG_ERR_CONFIG = 2,      /**< configuration invalid (zero baseline, zero step, non-finite value) */
    GG_ERR_NONFINITE = 3,   /**< an input was NaN or infinite */
    GG_ERR_RANGE = 4,       /**< an input was outside its physical range */
    GG_ERR_NOT_INIT = 5,    /**< module used before a successful init */
    GG_ERR_SEQUENCE = 6,    /**< frame out of sequence: gap, repeat or time stamp jump */
    GG_ERR_SENSOR = 7,      /**< a sensor flagged its own sample as bad */
    GG_ERR_NO_DATA = 8,     /**< HAL had no frame to deliver */
    GG_ERR_IO = 9           /**< HAL output failed */
} gg_status_t;

#endif /* GGINS_STATUS_H */
