-- | Laws over generated well-typed programs (Stref.Generate.Program): each
-- relates two ways of computing the same thing, so each can fail. Counts are
-- modest to keep CI fast; @stref explore@ runs the same generators longer.
module LawsSpec (spec) where

import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Checked (ArithOp (..))
import Stref.Conversions (convert)
import Stref.Diagnostics (RuntimeError (..))
import Stref.Engine (referenceEngine)
import Stref.Execution
import Stref.Explore.Naive
import Stref.Explore.Run
import Stref.Generate.Program
import Stref.Numeric (roundToReal)
import Stref.Operands
import Stref.Operators
import Stref.Policy
import Stref.Syntax.Parser (parseModule)
import Stref.Types
import Stref.Values
import Test.Hspec
import Test.QuickCheck

-- | Mapped inputs of every type, as the module generator declares them.
inputVars :: [(Text, BasicType, Operand)]
inputVars = [(n, t, o) | MappedVar n t o <- standardMapped]

-- | An expression over the inputs, the values of the inputs. Negative
-- literals (@-15@, @-1.5@) are literals (MT-LEX-14, MT-LEX-19), not unary
-- minus, so they never write INTERNAL_OVERFLOW.
data ExprCase = ExprCase BasicType TExpr (M.Map Text Value)

instance Show ExprCase where
  show (ExprCase t e env) = show t <> ": " <> show e <> "\n  inputs " <> show (M.toList env)

exprScope :: Scope
exprScope = Scope [(n, t) | (n, t, _) <- inputVars] True [] [] True

genExprCase :: Gen ExprCase
genExprCase = do
  t <- elements allBasicTypes
  e <- resize 8 (genExpr exprScope t)
  env <- M.fromList <$> mapM (\(n, ty, _) -> (n,) <$> genValue ty) inputVars
  pure (ExprCase t e env)

shrinkExprCase :: ExprCase -> [ExprCase]
shrinkExprCase (ExprCase t e env) = [ExprCase t e' env | e' <- shrinkTExpr e]

-- | The production operators composed the same way (left to right, the flag
-- threaded through): the evaluator the naive one is compared with before
-- any interpreter is involved.
kernelEval :: Policies -> M.Map Text Value -> Bool -> TExpr -> Either Int (Value, Bool)
kernelEval p env = go
  where
    go flag = \case
      TLit t l -> Right (litValue t l, flag)
      TVar _ v -> maybe (Left (-1)) (\x -> Right (x, flag)) (M.lookup v env)
      TFlag -> Right (VBool flag, flag)
      TWiden s t e -> (\(x, f) -> (convert p s t x, f)) <$> go flag e
      TConv s t e -> (\(x, f) -> (convert p s t x, f)) <$> go flag e
      TNeg _ e -> go flag e >>= \(x, _) -> apply flag (negateValue p x)
      TNot _ e -> (\(x, f) -> (notValue x, f)) <$> go flag e
      TArith op _ a b -> two flag a b >>= \(x, y, f) -> apply f (arith p op x y)
      TCmp op _ a b -> two flag a b >>= \(x, y, f) -> Right (VBool (compareValues op x y), f)
      TLogic op _ a b -> two flag a b >>= \(x, y, f) -> Right (logic op x y, f)
      TExpt _ a b -> two flag a b >>= \(x, y, f) -> apply f (expt p x y)
      TCall {} -> Left (-1)
      TIndex {} -> Left (-1)
    two flag a b = do
      (x, f1) <- go flag a
      (y, f2) <- go f1 b
      pure (x, y, f2)
    apply flag = fmap (\(v, o) -> (v, maybe flag id o))

-- | The module that evaluates an expression once: @RES := e; OV :=
-- INTERNAL_OVERFLOW;@ with the inputs in mapped operands.
expressionModule :: ExprCase -> GenModule
expressionModule (ExprCase t e env) =
  GenModule
    { gmMapped = [MappedVar n ty o | (n, ty, o) <- inputVars] ++ [MappedVar "RES" t (resultOperand t), MappedVar "OV" BOOL (OpBit KM 600 0)]
    , gmArrays = []
    , gmGlobals = []
    , gmInputs = [(o, v) | (n, _, o) <- inputVars, Just v <- [M.lookup n env]]
    , gmFunctions = []
    , gmProgram = GProgram [] [GAssign "RES" t e, GAssign "OV" BOOL TFlag]
    }
  where
    resultOperand = \case
      BOOL -> OpBit KM 600 1
      BYTE -> OpSimple KA 40
      USINT -> OpSimple KA 41
      WORD -> OpSimple KM 610
      INT -> OpSimple KM 611
      DWORD -> OpSimple KI 40
      DINT -> OpSimple KI 41
      REAL -> OpSimple KF 40

-- | Value and flag the production pipeline leaves in RES and OV, or the
-- runtime error code.
pipelineEval :: Policies -> ExprCase -> Either String (Either Int (Value, Bool))
pipelineEval p c@(ExprCase t _ _) = case runGenerated p (expressionModule c) of
  Left es -> Left ("rejected: " <> show es)
  Right (st, res) -> Right $ case crError res of
    Just err -> Left (reCode err)
    Nothing ->
      let mem = psMemory st
          find n = [o | MappedVar n' _ o <- gmMapped (expressionModule c), n' == n]
       in case (find "RES", find "OV") of
            ([r], [ov]) -> Right (readOperand mem r t, readOperand mem ov BOOL == VBool True)
            _ -> Left (-1)

genModuleWith :: GenConfig -> Gen GenModule
genModuleWith cfg = resize 20 (genModule cfg)

documentedErrors :: [Int]
documentedErrors = [2000, 2001, 2002, 2003, 2004, 2005, 2006, 2008, 2009, 2010, 2011, 2012, 2015, 2020, 2050]

spec :: Spec
spec = describe "Laws over generated programs" $ do
  describe "the generator" $ do
    it "produces expressions that follow its typing discipline, and shrinks that keep it" $
      withMaxSuccess 200 . forAll genExprCase $ \(ExprCase t e _) ->
        texprType e == t && wellFormed e && all wellFormed (shrinkTExpr e)
    it "writes REAL literals as decimals that round back to the same binary32" $
      withMaxSuccess 300 . forAll genFiniteReal $ \r ->
        let a = abs r in realBits (roundToReal (decimalOf a)) === realBits a

  describe "two evaluators agree" $ do
    it "the naive evaluator and the production operators agree on every expression (value and INTERNAL_OVERFLOW)" $
      withMaxSuccess 300 . forAllShrink genExprCase shrinkExprCase $ \(ExprCase _ e env) ->
        fmap (either Left Right) (naiveEval Saturate env False e) === Just (kernelEval mastertoolXE env False e)
    it "the naive evaluator and the interpreter agree on every expression (value and INTERNAL_OVERFLOW)" $
      withMaxSuccess 150 . forAllShrink genExprCase shrinkExprCase $ \c@(ExprCase _ e env) ->
        let naive = naiveEval Saturate env False e
         in counterexample (T.unpack (generatedSource (expressionModule c))) $
              fmap Right naive === Just (pipelineEval mastertoolXE c)
    it "they also agree under overflow = wrap" $
      withMaxSuccess 100 . forAllShrink genExprCase shrinkExprCase $ \c@(ExprCase _ e env) ->
        let p = mastertoolXE {pOverflow = Wrap}
         in counterexample (T.unpack (generatedSource (expressionModule c))) $
              fmap Right (naiveEval Wrap env False e) === Just (pipelineEval p c)

  describe "arithmetic saturation (MT-OP-6, MT-OP-7)" $ do
    let intTypes = [USINT, INT, DINT]
        genOperands = do
          t <- elements intTypes
          (,,) t <$> genValue t <*> genValue t
    it "saturated = exact result clamped, flag iff out of range" $
      withMaxSuccess 300 . forAll genOperands $ \(t, a, b) -> forAll (elements [OpAdd, OpSub, OpMul]) $ \op ->
        let Just (lo, hi) = intRange t
            Just x = valueToInteger a
            Just y = valueToInteger b
            exact = exactOf op x y
         in arith mastertoolXE op a b === Right (integerToValue t (max lo (min hi exact)), Just (exact < lo || exact > hi))
    it "under overflow = wrap: the exact result modulo 2^n, flag iff out of range" $
      withMaxSuccess 300 . forAll genOperands $ \(t, a, b) -> forAll (elements [OpAdd, OpSub, OpMul]) $ \op ->
        let Just (lo, hi) = intRange t
            Just x = valueToInteger a
            Just y = valueToInteger b
            exact = exactOf op x y
            wrapped = lo + (exact - lo) `mod` (hi - lo + 1)
         in arith mastertoolXE {pOverflow = Wrap} op a b === Right (integerToValue t wrapped, Just (exact < lo || exact > hi))

  describe "conversions (Table 4-6)" $ do
    it "widening then narrowing is the identity (the implicit edges, MT-CONV-6)" $
      withMaxSuccess 300 . forAll (elements [(s, t) | (s, t) <- implicitEdges, t /= REAL]) $ \(s, t) -> forAll (genValue s) $ \x ->
        convert mastertoolXE t s (convert mastertoolXE s t x) === x
    it "INT_TO_WORD then WORD_TO_INT is the identity (C39, C18)" $
      withMaxSuccess 300 . forAll (genValue INT) $ \x ->
        convert mastertoolXE WORD INT (convert mastertoolXE INT WORD x) === x
    it "REAL_TO_DINT(DINT_TO_REAL(x)) is within half the binary32 spacing of x (C49, C53)" $
      withMaxSuccess 300 . forAll (genValue DINT) $ \x ->
        let Just n = valueToInteger x
            Just back = valueToInteger (convert mastertoolXE REAL DINT (convert mastertoolXE DINT REAL x))
            spacing = 2 ^ max 0 (integerLog2 (abs n) - 23) :: Integer
         in counterexample (show (n, back)) (abs (back - n) <= max 1 (spacing `div` 2) || (n > 2147483520 && back == 2147483647))

  describe "whole generated modules" $ do
    it "print then parse is the identity" $
      withMaxSuccess 60 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        let src = generatedSource gm
         in counterexample (T.unpack src) $ case parseModule mastertoolXE "generated.st" src of
              Left e -> counterexample (show e) False
              Right m -> (() <$ m) === toModule gm
    it "the checker accepts every generated module" $
      withMaxSuccess 60 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        counterexample (T.unpack (generatedSource gm)) $ case checkGenerated mastertoolXE gm of
          Left es -> counterexample (show es) False
          Right _ -> property True
    it "the checker accepts every shrink of a generated module (shrinking keeps programs well typed)" $
      withMaxSuccess 25 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        conjoin
          [ counterexample (T.unpack (generatedSource small)) $ case checkGenerated mastertoolXE small of
              Left es -> counterexample (show es) False
              Right _ -> property True
          | let candidates = shrinkGenModule gm
                step = max 1 (length candidates `div` 40)
          , small <- everyNth step candidates
          ]
    it "every generated module ends in ok or a documented runtime error" $
      withMaxSuccess 60 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        counterexample (T.unpack (generatedSource gm)) $ case runGenerated mastertoolXE gm of
          Left es -> counterexample (show es) False
          Right (_, res) -> case crError res of
            Nothing -> property True
            Just err -> counterexample (show err) (reCode err `elem` documentedErrors)
    it "running the tree and running its printed source through the engine protocol give the same results" $
      withMaxSuccess 40 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        let direct = either (Left . show) (Right . observeDirect gm) (runGenerated mastertoolXE gm)
            viaEngine = summarise gm (Right (referenceEngine [] (explorationRequest mastertoolXE 1 "laws" gm)))
         in counterexample (T.unpack (generatedSource gm)) $ case (direct, viaEngine) of
              (Right (Observed pats (o1, o2, o3) code), SumRun ops outs code' _) ->
                (map (fmap Right) pats, [("OUTPUT1", Just o1), ("OUTPUT2", Just o2), ("OUTPUT3", Just o3)], code) === (ops, outs, code')
              _ -> counterexample (show (direct, viaEngine)) False
    it "name-resolution global-wins and local-wins agree when no local has a global's name" $
      withMaxSuccess 40 . forAll (genModuleWith defaultGenConfig) $ \gm ->
        let run p = observeDirect gm <$> either (Left . show) Right (runGenerated p gm)
         in run mastertoolXE === run mastertoolXE {pNameResolution = LocalWins}
    it "FOR with independent bounds runs max(0, (end - start) div step + 1) times under for-bounds = once" $
      withMaxSuccess 100 . forAll forCase $ \(start, end, step) ->
        let counter = MappedVar "N" DINT (OpSimple KI 50)
            body = [GAssign "N" DINT (TArith OpAdd DINT (TVar DINT "N") (TLit DINT (LitInt 1 10)))]
            gm = GenModule [counter] [] [] [] [] (GProgram [] [GAssign "N" DINT (TLit DINT (LitInt 0 10)), GFor "FC" INT start end (Just step) body])
            expected = max 0 ((end - start) `div` step + 1)
         in case runGenerated mastertoolXE gm of
              Left es -> counterexample (show es) False
              Right (st, _) -> readOperand (psMemory st) (OpSimple KI 50) DINT === VDInt (fromInteger expected)
  where
    everyNth k xs = case xs of
      [] -> []
      (x : rest) -> x : everyNth k (drop (k - 1) rest)
    exactOf op x y = case op of
      OpAdd -> x + y
      OpSub -> x - y
      _ -> x * y
    integerLog2 :: Integer -> Int
    integerLog2 n = if n < 2 then 0 else 1 + integerLog2 (n `div` 2)
    forCase = do
      start <- choose (-300, 300)
      end <- choose (-300, 300)
      step <- elements ([1 .. 7] ++ [-1, -2, -3, -5])
      pure (start, end, step)
