#include <stdio.h>
#include <math.h>
#include <time.h>
#include <gsl/gsl_errno.h>
#include "tendonrod.h"
#include "tr_internal.h"
static double now(void){struct timespec t; clock_gettime(CLOCK_PROCESS_CPUTIME_ID,&t); return t.tv_sec+1e-9*t.tv_nsec;}
int main(void){
  gsl_set_error_handler_off();
  double L=0.1, dd=1.04e-3, E=210e9, G=80e9, A=M_PI*dd*dd/4, I=M_PI*pow(dd,4)/64, EI=E*I, r=0.01;
  double rod[6]={L,EI,G*2*I,E*A,G*A,1}; double z3[3]={0,0,0};
  double td[24]; for(int i=0;i<3;i++){double row[8]={r,2*M_PI*i/3,0,50*3*EI/(r*r),L,1,i==0?EI*M_PI/2/(r*L):0.5,0}; for(int j=0;j<8;j++) td[8*i+j]=row[j];}
  double ld[7]={L,0,0.5,0,0,0,0};
  tr_options o=tr_default_options(); o.steps=3; char msg[512]; tr_model *m; 
  for (int kir=1; kir>=0; kir--) {
  rod[5]=kir;
  tr_model_alloc(&m, rod, td, 3, ld, 1, z3, &o, msg, 512);
  tr_data *d=tr_data_alloc(m,&o,101,NULL,msg,512);
  tr_solve(m,d,NULL,NULL);
  double y[40], dy[40]; 
  // state at mid: use s=0 base state from solution
  for(int i=0;i<40;i++) y[i]=0; y[3]=y[7]=y[11]=1; y[12]=0.1; y[13]=0.2; y[14]=-1; y[15]=0.01; y[16]=0.03; y[17]=0.001;
  d->rec=0; d->seg=0; for(int i=0;i<3;i++) d->tau[i]=1.0+i;
  int N=2000000; double t0=now(); double acc=0;
  for(int it=0; it<N; it++){ y[15]=0.01+1e-9*it; tr_rhs(0.05, y, dy, d); acc+=dy[16]; }
  double t1=now();
  printf("kirchhoff=%d rhs %.1f ns (acc %g)\n", kir, (t1-t0)/N*1e9, acc);
  // integration
  double x[9]; for(int i=0;i<d->k;i++) x[i]=d->x[i]; double f[9];
  t0=now(); for(int it=0; it<20000; it++) tr_residual(m,d,x,f); t1=now();
  printf("  residual (3 steps rk8) %.2f us\n", (t1-t0)/20000*1e6);
  tr_data_free(d); tr_model_free(m);
  }
}
